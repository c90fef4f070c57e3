// A brute-force reference for the FCP on separated pairs: the largest gap over the face normals
// of A and B and the edge-edge cross products that are faces of the Minkowski difference (both
// edges are the supports of their bodies along the normal), by full vertex scans.
#pragma once

#include <algorithm>
#include <limits>

#include "contact_test_util.h"
#include "polydem/contact/contact.h"
#include "polydem/contact/fcp/fcp.h"

namespace polydem::contact::testing {

/// Whether vertices i and j of `body` both reach the maximum of m . x within tol.
inline bool edgeIsSupport(const Body& body, int i, int j, const Vec3& m, double tol) {
  double top = -std::numeric_limits<double>::infinity();
  for (const Vec3& x : body.vertices) top = std::max(top, m.dot(x));
  return m.dot(body.vertices[i]) >= top - tol && m.dot(body.vertices[j]) >= top - tol;
}

struct GapResult {
  double gap = -std::numeric_limits<double>::infinity();
  Vec3 normal = Vec3::UnitZ();
};

/// Largest gap (= -overlapAlong) over the FCP's candidate set, by brute force. For overlapping
/// pairs it equals -satPenetration().depth; for separated pairs the plain SAT set may do better
/// along a cross product of two edges that do not face each other, which no common plane is.
inline GapResult bruteForceCommonPlane(const Body& a, const Body& b) {
  GapResult best;
  const auto consider = [&](const Vec3& m) {
    const double g = -overlapAlong(a, b, m);
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
        if (edgeIsSupport(b, eb.v0, eb.v1, m, tol) && edgeIsSupport(a, ea.v0, ea.v1, -m, tol)) {
          consider(m);
        }
      }
    }
  }
  return best;
}

}  // namespace polydem::contact::testing
