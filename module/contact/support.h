// Support mappings of placed polyhedra and of their Minkowski difference A - B, shared by GJK and
// EPA (gjk.h, epa.h) and by the IPM's plane placement (ipm.h).
#pragma once

#include "polydem/contact/contact.h"

namespace polydem::contact {

/// Up to this many vertices a support query scans the world vertices (a few dot products, no
/// rotation); above, it rotates the direction into the body frame and hill-climbs the vertex graph
/// (ConvexPolyhedron::supportIndex), starting from the previous answer.
inline constexpr int kScanSupportVertices = 32;

/// Index of a world vertex of `body` maximising direction . x. `hint` is the previous answer for
/// a nearby direction (only used by the hill climb). Ties go to the lowest index on a scan.
inline int supportIndex(const Body& body, const Vec3& direction, int hint = 0) {
  const int n = static_cast<int>(body.vertices.size());
  if (n > kScanSupportVertices) {
    return body.shape->supportIndex(body.rotation.transpose() * direction, hint);
  }
  const Vec3* v = body.vertices.data();
  int best = 0;
  double best_value = direction.dot(v[0]);
  for (int i = 1; i < n; ++i) {
    const double value = direction.dot(v[i]);
    if (value > best_value) {
      best = i;
      best_value = value;
    }
  }
  return best;
}

/// A point of the Minkowski difference A - B with the vertices of A and B it came from. No default
/// member values: EPA keeps hundreds of them in an uninitialised array.
struct SupportPoint {
  Vec3 w;  // a - b
  int ia;  // index into a.vertices
  int ib;  // index into b.vertices
};

/// Support of A - B along `direction`: A's support along d minus B's along -d. Keeps the last
/// indices as hints for the next query.
class MinkowskiSupport {
 public:
  MinkowskiSupport(const Body& a, const Body& b) : a_(a), b_(b) {}

  SupportPoint operator()(const Vec3& direction) {
    hint_a_ = supportIndex(a_, direction, hint_a_);
    hint_b_ = supportIndex(b_, -direction, hint_b_);
    return {a_.vertices[hint_a_] - b_.vertices[hint_b_], hint_a_, hint_b_};
  }

  const Body& a() const { return a_; }
  const Body& b() const { return b_; }

 private:
  const Body& a_;
  const Body& b_;
  int hint_a_ = 0, hint_b_ = 0;
};

/// Length scale of a pair for relative tolerances: the sum of the two circumradii.
inline double pairLengthScale(const Body& a, const Body& b) {
  return a.circumradius() + b.circumradius();
}

}  // namespace polydem::contact
