// Helpers shared by the lp kernel's tests: placed bodies that own their shape and vertices.
#pragma once

#include <random>
#include <vector>

#include "polydem/contact/contact.h"
#include "polydem/geometry/convex_polyhedron.h"

namespace polydem::contact::testing {

/// A body that owns its shape and world vertices (not copyable: Body points into both).
struct Placed {
  geometry::ConvexPolyhedron shape;
  std::vector<Vec3> storage;
  Body body;
  explicit Placed(const std::vector<Vec3>& points, const Mat3& rotation = Mat3::Identity(),
                  const Vec3& position = Vec3::Zero())
      : shape(geometry::ConvexPolyhedron::fromPoints(points)) {
    body = placeBody(shape, position, rotation, storage);
  }
  Placed(const Placed&) = delete;
  Placed& operator=(const Placed&) = delete;
};

inline Mat3 randomRotation(std::mt19937_64& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  return Quat(n(rng), n(rng), n(rng), n(rng)).normalized().toRotationMatrix();
}

inline Vec3 randomUnit(std::mt19937_64& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  return Vec3(n(rng), n(rng), n(rng)).normalized();
}

/// The world planes n . x <= d of a placed body's faces.
struct WorldPlane {
  Vec3 normal;
  double offset;
};
inline std::vector<WorldPlane> worldPlanes(const Body& b) {
  std::vector<WorldPlane> planes;
  for (const auto& f : b.shape->faces()) {
    const Vec3 n = b.rotation * f.normal;
    planes.push_back({n, f.offset + n.dot(b.position)});
  }
  return planes;
}

}  // namespace polydem::contact::testing
