// Water pressure on the joint faces of the free blocks (water.h).
#include "polydem/sim/water.h"

#include <algorithm>
#include <array>

namespace polydem::sim {

namespace {

// The heights of the table at `time` (the level, or the three points' heights), linear between
// rows; no allocation, as it runs every step.
std::array<double, 3> heightsAt(const setup::WaterSpec& water, double time) {
  const auto& t = water.times;
  std::size_t lo = 0, hi = 0;  // rows to blend, and the weight of `hi`
  double s = 0.0;
  if (time >= t.back()) {
    lo = hi = t.size() - 1;
  } else if (time > t.front()) {
    hi = static_cast<std::size_t>(std::upper_bound(t.begin(), t.end(), time) - t.begin());
    lo = hi - 1;  // t[lo] <= time < t[hi]
    s = (time - t[lo]) / (t[hi] - t[lo]);
  }
  std::array<double, 3> z{};
  for (std::size_t i = 0; i < water.heights[lo].size() && i < z.size(); ++i) {
    z[i] = water.heights[lo][i] + s * (water.heights[hi][i] - water.heights[lo][i]);
  }
  return z;
}

}  // namespace

PhreaticSurface phreaticSurface(const setup::WaterSpec& water, double time) {
  const std::array<double, 3> z = heightsAt(water, time);
  PhreaticSurface s;
  if (water.points.empty()) {
    s.height = z[0];
    return s;
  }
  // The plane through the three points (x_i, y_i, z_i): solve for the slopes from the two
  // differences to the first point (Cramer's rule; the reader refused collinear points).
  const auto& p = water.points;
  const double ux = p[1][0] - p[0][0], uy = p[1][1] - p[0][1], uz = z[1] - z[0];
  const double vx = p[2][0] - p[0][0], vy = p[2][1] - p[0][1], vz = z[2] - z[0];
  const double det = ux * vy - uy * vx;
  s.x0 = p[0][0];
  s.y0 = p[0][1];
  s.height = z[0];
  s.slope_x = (uz * vy - uy * vz) / det;
  s.slope_y = (ux * vz - uz * vx) / det;
  return s;
}

geometry::LinearPressure hydrostaticPressure(const PhreaticSurface& surface, double unit_weight,
                                             const Vec3& c) {
  geometry::LinearPressure pressure;
  pressure.origin = c;
  pressure.value = unit_weight * (surface.at(c.x(), c.y()) - c.z());
  pressure.gradient = unit_weight * Vec3(surface.slope_x, surface.slope_y, -1.0);
  return pressure;
}

void faceWaterPressures(const setup::WaterSpec& water, double time,
                        const geometry::BodyShape& shape, std::span<const Vec3> vertices,
                        std::span<const Vec3> normals, const Vec3& centroid,
                        std::vector<double>& out) {
  const auto& faces = shape.polyhedron.faces();
  out.assign(faces.size(), 0.0);
  if (shape.face_plane.empty()) return;
  const auto pressure =
      hydrostaticPressure(phreaticSurface(water, time), water.unit_weight, centroid);
  for (std::size_t f = 0; f < faces.size(); ++f) {
    if (shape.face_plane[f] < 0) continue;
    const auto r = geometry::pressureResultant(vertices, faces[f].vertices, normals[f], pressure);
    out[f] = r.load / faces[f].area;
  }
}

void addWaterForces(const setup::WaterSpec& water, double time, const particles::ShapeTable& shapes,
                    const particles::ParticleStorage& particles,
                    std::span<dynamics::ForceAccumulator> forces) {
  const PhreaticSurface surface = phreaticSurface(water, time);
  const double gw = water.unit_weight;
  for (std::size_t i = 0; i < forces.size(); ++i) {
    const auto& p = particles[i];
    const geometry::BodyShape& shape = shapes[p.shape];
    if (!p.isFree() || shape.face_plane.empty()) continue;
    // p(x) = gamma_w (z_surface(x, y) - z), about the block's centroid.
    const auto pressure = hydrostaticPressure(surface, gw, particles.placedPosition(i));
    const auto vertices = particles.worldVertices(i);
    const auto normals = particles.worldFaceNormals(i);
    const auto& faces = shape.polyhedron.faces();
    for (std::size_t f = 0; f < faces.size(); ++f) {
      if (shape.face_plane[f] < 0) continue;
      const auto r = geometry::pressureResultant(vertices, faces[f].vertices, normals[f], pressure);
      if (r.load > 0.0) forces[i].addPair(r.force, r.moment);
    }
  }
}

}  // namespace polydem::sim
