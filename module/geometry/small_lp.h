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
/// Scale the problem so that |rows| ~ 1 and |b| ~ 1 for best accuracy.
SmallLpResult solveSmallLp(std::span<const Vec4> rows, std::span<const double> b, const Vec4& c);

}  // namespace polydem::geometry
