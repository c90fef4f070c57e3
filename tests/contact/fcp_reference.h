// Independent references for the FCP tests: brute-force separating-axis gaps over every candidate
// normal (full vertex scans, no topology walks, no cone tests), random poses and random pairs.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "contact/contact.h"
#include "contact/fcp.h"
#include "geometry/convex_polyhedron.h"

namespace polydem::contact::testing {

/// gap(m) = min over A of m.a - max over B of m.b, by scanning every vertex.
inline double scanGap(const Body& a, const Body& b, const Vec3& m) {
  double lo = std::numeric_limits<double>::infinity();
  double hi = -std::numeric_limits<double>::infinity();
  for (const Vec3& x : a.vertices) lo = std::min(lo, m.dot(x));
  for (const Vec3& x : b.vertices) hi = std::max(hi, m.dot(x));
  return lo - hi;
}

struct SatResult {
  double gap = -std::numeric_limits<double>::infinity();
  Vec3 normal = Vec3::UnitZ();
};

/// Whether the vertices of `body` at indices i and j both reach the extreme max of m.x (within
/// tol): the body's support along m contains that edge.
inline bool edgeIsSupport(const Body& body, int i, int j, const Vec3& m, double tol) {
  double top = -std::numeric_limits<double>::infinity();
  for (const Vec3& x : body.vertices) top = std::max(top, m.dot(x));
  return m.dot(body.vertices[i]) >= top - tol && m.dot(body.vertices[j]) >= top - tol;
}

/// Largest gap over every face normal of A (inward) and B (outward) and both orientations of the
/// cross product of every edge of A with every edge of B (parallel ones skipped). With
/// `minkowski_faces_only` an edge-pair normal counts only where both edges are the supports of
/// their bodies along it (a face of the Minkowski difference), which is the candidate set of the
/// FCP for separated pairs; for overlapping pairs both sets give the same maximum.
inline SatResult bruteForceSat(const Body& a, const Body& b, bool minkowski_faces_only = false) {
  SatResult best;
  const auto consider = [&](const Vec3& m) {
    const double g = scanGap(a, b, m);
    if (g > best.gap) best = {g, m};
  };
  for (const auto& f : a.shape->faces()) consider(-(a.rotation * f.normal));
  for (const auto& f : b.shape->faces()) consider(b.rotation * f.normal);
  const double tol = 1e-12 * (a.circumradius() + b.circumradius());
  for (const auto& ea : a.shape->edges()) {
    const Vec3 da = a.vertices[ea.v1] - a.vertices[ea.v0];
    for (const auto& eb : b.shape->edges()) {
      const Vec3 db = b.vertices[eb.v1] - b.vertices[eb.v0];
      const Vec3 c = da.cross(db);
      if (c.norm() <= kFcpParallelSine * da.norm() * db.norm()) continue;
      for (const Vec3& m : {Vec3(c.normalized()), Vec3(-c.normalized())}) {
        if (minkowski_faces_only &&
            !(edgeIsSupport(b, eb.v0, eb.v1, m, tol) && edgeIsSupport(a, ea.v0, ea.v1, -m, tol))) {
          continue;
        }
        consider(m);
      }
    }
  }
  return best;
}

/// Uniformly random rotation (normalised Gaussian quaternion).
inline Mat3 randomRotation(std::mt19937_64& rng) {
  std::normal_distribution<double> g;
  Quat q(g(rng), g(rng), g(rng), g(rng));
  q.normalize();
  return q.toRotationMatrix();
}

inline Vec3 randomUnit(std::mt19937_64& rng) {
  std::normal_distribution<double> g;
  return Vec3(g(rng), g(rng), g(rng)).normalized();
}

/// A shape and its placement, owning the world vertices.
struct Placed {
  const geometry::ConvexPolyhedron* shape = nullptr;
  std::vector<Vec3> storage;
  Body body;
  Placed() = default;
  Placed(const geometry::ConvexPolyhedron& s, const Vec3& position, const Mat3& rotation)
      : shape(&s) {
    body = placeBody(s, position, rotation, storage);
  }
  Placed(const Placed& o) : Placed(*o.shape, o.body.position, o.body.rotation) {}
  Placed& operator=(const Placed& o) {
    shape = o.shape;
    body = placeBody(*o.shape, o.body.position, o.body.rotation, storage);
    return *this;
  }
};

}  // namespace polydem::contact::testing
