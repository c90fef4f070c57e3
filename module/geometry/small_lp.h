// A dense linear-programme solver written for four unknowns.
//
// Two problems in polydem are tiny LPs over the face planes of one or two polyhedra:
//  - the inscribed sphere of a polyhedron (Chebyshev centre): maximise r s.t. n_i.x + r <= d_i;
//  - the potential-block contact test of Boon et al. (2012): minimise s s.t. a_i.x - s <= d_i
//    over the faces of both blocks; s < 0 means the blocks overlap.
// Both have the form  minimise c.z  subject to  A z <= b,  z in R^4 free.  The solver works on
// the dual (4 equality rows, m >= 0 columns) with a 4x4 basis, so each pivot costs O(m).
#pragma once

#include <Eigen/Core>
#include <span>

namespace polydem::geometry {

using Vec4 = Eigen::Vector4d;

struct SmallLpResult {
  enum class Status { kOptimal, kInfeasible, kUnbounded };
  Status status = Status::kInfeasible;
  Vec4 z = Vec4::Zero();  // the minimiser, when optimal
  double objective = 0.0;
  int iterations = 0;
};

/// Minimises c.z subject to rows[i].z <= b[i] for all i. Deterministic (no randomisation).
/// Rows are scaled to unit length internally and tolerances are relative to the problem's size,
/// so the same problem in other units gives the same answer in those units. No heap allocation
/// up to 64 rows.
SmallLpResult solveSmallLp(std::span<const Vec4> rows, std::span<const double> b, const Vec4& c);

/// The solver's anti-cycling and refactoring rules. The defaults suit every use in polydem; tests
/// change them to drive each path on every instance.
struct SmallLpOptions {
  int bland_after = 8;  // consecutive degenerate pivots before Bland's rule takes over (0: always)
  int refactor_every = 16;  // pivots between recomputations of the basis inverse from its rows
};
SmallLpResult solveSmallLp(std::span<const Vec4> rows, std::span<const double> b, const Vec4& c,
                           const SmallLpOptions& options);

}  // namespace polydem::geometry
