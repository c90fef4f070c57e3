// EPA, the expanding polytope algorithm (van den Bergen 2001): from a GJK simplex enclosing the
// origin, grows a polytope inside A - B towards the face of A - B closest to the origin. That
// face's distance is the penetration depth, its outward normal the direction in which the origin
// leaves A - B, i.e. minus the direction in which A must move to separate.
//
// The contact point is EPA's barycentric point (Keissar eqs. 2.1-2.2): the origin's projection c
// onto the closest face is written as c = sum xi_i w_i over the face's corners w_i = a_i - b_i, and
// the point is (sum xi_i a_i + sum xi_i b_i) / 2. On face-face, edge-face and parallel-edge
// contacts the closest face of A - B is one triangle of a flat region of A - B; which one depends
// on the history of the expansion, so the point lands off the centre of the contact patch (Keissar
// section 2.2). This is reproduced on purpose: gjk-epa-ipm replaces the point (ipm.h).
#pragma once

#include "polydem/contact/gjk/gjk.h"

namespace polydem::contact {

struct EpaResult {
  bool touching = false;        // depth > 0
  Vec3 normal = Vec3::UnitZ();  // unit, from B into A
  double depth = 0.0;
  Vec3 point = Vec3::Zero();  // barycentric contact point, Keissar eqs. 2.1-2.2
  bool converged = true;      // false when a bound was hit or the polytope became inconsistent
  int iterations = 0;
  /// EPA's last support query along the normal: A's vertex lowest along it and B's highest
  /// (indices into the bodies' vertices; -1 when there was none). They bound the overlap along
  /// the normal, e.g. for the IPM's plane in the middle of it.
  int lowest_a = -1, highest_b = -1;
};

/// Vertices the polytope may hold; bounds the iterations at kEpaMaxVertices - 4.
inline constexpr int kEpaMaxVertices = 256;

/// Runs EPA from the simplex GJK ended with (the origin in its hull or within `tolerance` of it;
/// lower-dimensional simplices are blown up to a tetrahedron with further support points).
/// Stops when the support of A - B along the closest face's normal lies at most `tolerance` (a
/// length, relative to the pair's size) beyond that face. No heap allocation: the polytope lives
/// in fixed arrays on the stack (about 48 KiB).
EpaResult epaPenetration(MinkowskiSupport& support, const Simplex& simplex, double tolerance);

}  // namespace polydem::contact
