#include "generators/pile_scene.h"

#include <algorithm>
#include <cmath>
#include <random>

#include "polydem/core/error.h"
#include "polydem/geometry/shapes.h"

namespace polydem::sim {

namespace {

setup::ShapeSpec shape(std::string name, std::vector<Vec3> vertices) {
  return {std::move(name), std::move(vertices), 0};
}

std::vector<Vec3> centred(std::vector<Vec3> v) {
  Vec3 c = Vec3::Zero();
  for (const auto& x : v) c += x;
  c /= static_cast<double>(v.size());
  for (auto& x : v) x -= c;
  return v;
}

}  // namespace

setup::Setup makePileScene(const PileOptions& o) {
  if (o.particles < 1 || o.layers < 1) throw Error("pile: particles and layers must be >= 1");
  if (o.floor_width != 0 && !(o.floor_width >= 1)) {
    throw Error("pile: the floor width must be 0 (walls) or at least 1 (times the pile's)");
  }
  setup::Setup s;
  s.file = "<generated P-PILE>";
  s.id = "P-PILE";
  s.title = "pile of convex polyhedra settling in a box";
  s.kernel = o.kernel;
  s.dt = 1e-4;
  s.steps = o.steps;
  s.gravity = Vec3(0, 0, -9.81);

  particles::Material rock;
  rock.name = "rock";
  rock.density = 2650;
  rock.kn = 1e8;
  rock.ks = 5e7;
  rock.friction_angle = 30;
  rock.local_damping = 0.1;
  rock.penalty = 1e9;
  s.materials.push_back(rock);

  const bool cubes = o.shapes == "cubes";
  if (cubes) {
    s.shapes.push_back(
        shape("cube", geometry::shapes::box(Vec3(-0.5, -0.5, -0.5), Vec3(0.5, 0.5, 0.5))));
  } else if (o.shapes == "mixed") {
    // Circumradii all about 0.5: cube 0.6, tetrahedron 0.85, octahedron 0.72 (edges).
    s.shapes.push_back(
        shape("cube", geometry::shapes::box(Vec3(-0.3, -0.3, -0.3), Vec3(0.3, 0.3, 0.3))));
    s.shapes.push_back(shape("tetrahedron", centred(geometry::shapes::tetrahedron(0.85))));
    s.shapes.push_back(shape("octahedron", centred(geometry::shapes::octahedron(0.72))));
    for (int n : {8, 16, 40}) {
      s.shapes.push_back(shape("random" + std::to_string(n), centred(geometry::shapes::randomConvex(
                                                                 n, 7 + n, Vec3(0.5, 0.4, 0.35)))));
    }
  } else {
    throw Error("pile: shapes must be \"mixed\" or \"cubes\", not \"" + o.shapes + "\"");
  }
  // Lattice pitch: aligned cubes may sit a small gap apart; turned shapes need their bounding
  // spheres (radius about the vertex mean, plus 10% for the offset of the centroid) apart.
  double radius = 0.0;
  for (const auto& sh : s.shapes) {
    for (const auto& v : sh.vertices) radius = std::max(radius, v.norm());
  }
  const double pitch = cubes ? 1.0 + o.gap : 2.0 * 1.1 * radius * (1.0 + o.gap);
  const auto layers = o.layers;
  const auto side = static_cast<std::int64_t>(
      std::ceil(std::sqrt(static_cast<double>(o.particles) / static_cast<double>(layers))));
  const double width = static_cast<double>(side) * pitch;

  // Floor and walls: fixed boxes around the footprint [0, width]^2 (or a wide floor alone).
  const int wall_shape = static_cast<int>(s.shapes.size());
  const double t = kPileBoxThickness;
  const bool wide = o.floor_width > 0;
  const double rim = wide ? 0.5 * (o.floor_width - 1.0) * width : t;
  Uid uid = addPileBox(s, width, static_cast<double>(layers) * pitch + 2.0, rim, !wide, 1);

  std::mt19937_64 rng(o.seed);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::normal_distribution<double> gauss;
  for (std::int64_t i = 0; i < o.particles; ++i) {
    const std::int64_t ix = i % side, iy = (i / side) % side, iz = i / (side * side);
    setup::ParticleSpec p;
    p.uid = uid++;
    p.shape = cubes ? 0 : static_cast<int>(i % wall_shape);
    p.material = 0;
    p.position =
        Vec3((static_cast<double>(ix) + 0.5) * pitch, (static_cast<double>(iy) + 0.5) * pitch,
             (static_cast<double>(iz) + 0.5) * pitch + 0.01);
    if (!cubes) {
      p.orientation = Quat(gauss(rng), gauss(rng), gauss(rng), gauss(rng)).normalized();
    }
    p.velocity = o.initial_speed * Vec3(unit(rng), unit(rng), unit(rng));
    s.particles.push_back(p);
  }
  s.output.series_every = 1000000;
  return s;
}

Uid addPileBox(setup::Setup& s, double width, double height, double rim, bool walls, Uid uid) {
  const int floor = static_cast<int>(s.shapes.size());
  const double t = kPileBoxThickness;
  s.shapes.push_back(shape(
      "floor", geometry::shapes::box(Vec3(-rim, -rim, -t), Vec3(width + rim, width + rim, 0))));
  auto fixed = [&](int shape_index, const Vec3& offset) {
    setup::ParticleSpec p;
    p.uid = uid++;
    p.shape = shape_index;
    p.material = 0;
    p.position = offset;
    p.fixed = true;
    s.particles.push_back(p);
  };
  fixed(floor, Vec3::Zero());
  if (!walls) return uid;
  s.shapes.push_back(
      shape("wall_x", geometry::shapes::box(Vec3(-t, -t, 0), Vec3(0, width + t, height))));
  s.shapes.push_back(
      shape("wall_y", geometry::shapes::box(Vec3(0, -t, 0), Vec3(width, 0, height))));
  fixed(floor + 1, Vec3::Zero());
  fixed(floor + 1, Vec3(width + t, 0, 0));
  fixed(floor + 2, Vec3::Zero());
  fixed(floor + 2, Vec3(0, width + t, 0));
  s.domain.min = Vec3(-t - 0.5, -t - 0.5, -t - 0.5);
  s.domain.max = Vec3(width + t + 0.5, width + t + 0.5, height + 0.5);
  return uid;
}

}  // namespace polydem::sim
