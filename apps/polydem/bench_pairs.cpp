// The three pair sets of polydem bench kernels, generated from fixed seeds (std::mt19937_64, so
// the same pairs on every machine).
#include <cmath>
#include <random>

#include "bench_kernels.h"
#include "polydem/geometry/polygon.h"
#include "polydem/geometry/shapes.h"

namespace polydem::app {

namespace {

Mat3 randomRotation(std::mt19937_64& rng) {
  std::normal_distribution<double> g(0.0, 1.0);
  Quat q(g(rng), g(rng), g(rng), g(rng));
  return q.normalized().toRotationMatrix();
}

Vec3 randomUnit(std::mt19937_64& rng) {
  std::normal_distribution<double> g(0.0, 1.0);
  return Vec3(g(rng), g(rng), g(rng)).normalized();
}

const geometry::ConvexPolyhedron* keep(PairSet& set, geometry::ConvexPolyhedron shape) {
  set.shapes.push_back(std::make_unique<geometry::ConvexPolyhedron>(std::move(shape)));
  return set.shapes.back().get();
}

struct Placement {
  const geometry::ConvexPolyhedron* shape;
  Vec3 position;
  Mat3 rotation;
};

/// Fills world vertices and bodies once every placement is known (the bodies point into `world`).
void build(PairSet& set, const std::vector<Placement>& a, const std::vector<Placement>& b) {
  set.world.resize(a.size() + b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    set.a.push_back(contact::placeBody(*a[i].shape, a[i].position, a[i].rotation, set.world[i]));
    set.b.push_back(
        contact::placeBody(*b[i].shape, b[i].position, b[i].rotation, set.world[a.size() + i]));
  }
}

}  // namespace

PairSet faceFacePairs(int n, std::uint64_t seed) {
  PairSet set;
  set.name = "face-face";
  const auto* cube = keep(set, geometry::ConvexPolyhedron::fromPoints(geometry::shapes::cube(1)));
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<Placement> a, b;
  std::vector<Vec2> patch, scratch;
  const std::vector<Vec2> top = {{-0.5, -0.5}, {0.5, -0.5}, {0.5, 0.5}, {-0.5, 0.5}};
  for (int i = 0; i < n; ++i) {
    const double depth = std::pow(10.0, -5.0 + 2.0 * unit(rng));
    const Vec2 shift(0.4 * unit(rng) - 0.2, 0.4 * unit(rng) - 0.2);
    const double yaw = (unit(rng) - 0.5) * kPi / 2.0;
    const Mat3 pose = randomRotation(rng);
    const Vec3 origin = 10.0 * Vec3(unit(rng), unit(rng), unit(rng));
    const Mat3 turn = Eigen::AngleAxisd(yaw, Vec3::UnitZ()).toRotationMatrix();
    a.push_back({cube, origin + pose * Vec3(shift.x(), shift.y(), 0.5 - depth), pose * turn});
    b.push_back({cube, origin + pose * Vec3(0.0, 0.0, -0.5), pose});
    // The exact patch: A's footprint (the turned square) clipped by B's top face.
    std::vector<Vec2> footprint;
    for (const Vec2& c : top) footprint.push_back(shift + turn.topLeftCorner<2, 2>() * c);
    geometry::intersectConvex(footprint, top, patch, scratch);
    const Vec2 centre = geometry::areaCentroid(patch).centroid;
    set.exact_point.push_back(origin + pose * Vec3(centre.x(), centre.y(), -0.5 * depth));
  }
  build(set, a, b);
  return set;
}

PairSet randomCubePairs(int n, std::uint64_t seed) {
  PairSet set;
  set.name = "random-cubes";
  const auto* cube = keep(set, geometry::ConvexPolyhedron::fromPoints(geometry::shapes::cube(1)));
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<Placement> a, b;
  for (int i = 0; i < n; ++i) {
    // Centres closer than 1: the inscribed balls (radius 1/2) overlap, so the cubes do.
    const Vec3 origin = 10.0 * Vec3(unit(rng), unit(rng), unit(rng));
    const double distance = 0.6 + 0.4 * unit(rng);
    a.push_back({cube, origin + distance * randomUnit(rng), randomRotation(rng)});
    b.push_back({cube, origin, randomRotation(rng)});
  }
  build(set, a, b);
  return set;
}

PairSet randomPolyhedronPairs(int n, std::uint64_t seed) {
  PairSet set;
  set.name = "random-polyhedra";
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::uniform_int_distribution<int> count(8, 40);
  std::vector<Placement> a, b;
  for (int i = 0; i < n; ++i) {
    const geometry::ConvexPolyhedron* shape[2];
    for (auto& s : shape) {
      const Vec3 axes(0.5 + 0.5 * unit(rng), 0.5 + 0.5 * unit(rng), 0.5 + 0.5 * unit(rng));
      s = keep(set, geometry::ConvexPolyhedron::fromPoints(
                        geometry::shapes::randomConvex(count(rng), rng(), axes, 0.2)));
    }
    // Incentres closer than the sum of the inradii: the inscribed balls overlap.
    const Mat3 ra = randomRotation(rng), rb = randomRotation(rng);
    const Vec3 origin = 10.0 * Vec3(unit(rng), unit(rng), unit(rng));
    const double distance = (0.6 + 0.4 * unit(rng)) * (shape[0]->inradius() + shape[1]->inradius());
    const Vec3 centre_a = origin + distance * randomUnit(rng);
    a.push_back({shape[0], centre_a - ra * shape[0]->incenter(), ra});
    b.push_back({shape[1], origin - rb * shape[1]->incenter(), rb});
  }
  build(set, a, b);
  return set;
}

}  // namespace polydem::app
