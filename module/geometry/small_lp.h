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
#include <array>
#include <span>

namespace polydem::geometry {

using Vec4 = Eigen::Vector4d;

struct SmallLpResult {
  enum class Status { kOptimal, kInfeasible, kUnbounded };
  Status status = Status::kInfeasible;
  Vec4 z = Vec4::Zero();  // the minimiser, when optimal
  double objective = 0.0;
  int iterations = 0;
  /// When optimal: the optimal basis, as the caller's indices of the four rows whose planes meet
  /// at z (-1 for an artificial box row of the solver: the optimum is then not a vertex of the
  /// rows), and their multipliers y >= 0 with -c = sum_k y_k rows[basis[k]] (the dual solution,
  /// rows taken at unit length: y_k multiplies rows[basis[k]] / |rows[basis[k]]|).
  std::array<int, 4> basis{-1, -1, -1, -1};
  Vec4 multipliers = Vec4::Zero();
};

/// Minimises c.z subject to rows[i].z <= b[i] for all i. Deterministic (no randomisation).
/// Rows are scaled to unit length internally and tolerances are relative to the problem's size,
/// so the same problem in other units gives the same answer in those units. No heap allocation
/// up to 64 rows; above, a per-thread buffer grows once and is reused.
SmallLpResult solveSmallLp(std::span<const Vec4> rows, std::span<const double> b, const Vec4& c);

/// The solver's anti-cycling and refactoring rules. The defaults suit every use in polydem; tests
/// change them to drive each path on every instance.
struct SmallLpOptions {
  int bland_after = 8;  // consecutive degenerate pivots before Bland's rule takes over (0: always)
  int refactor_every = 16;  // pivots between recomputations of the basis inverse from its rows
};
SmallLpResult solveSmallLp(std::span<const Vec4> rows, std::span<const double> b, const Vec4& c,
                           const SmallLpOptions& options);

/// Warm start: starts the dual simplex from `basis`, four row indices (typically the optimal
/// basis of a nearby problem, e.g. the same rows moved a little since the last time step). The
/// basis is used when its rows are distinct, well conditioned (|det| >= 1e-8 at unit length) and
/// dual feasible for this problem (multipliers >= 0); a vertex that violates rows is then a few
/// pivots from the optimum. Otherwise (or with a -1 entry) the solve starts cold. The answer is
/// the cold solve's up to the choice among several optimal vertices.
SmallLpResult solveSmallLp(std::span<const Vec4> rows, std::span<const double> b, const Vec4& c,
                           const std::array<int, 4>& basis,
                           const SmallLpOptions& options = SmallLpOptions{});

}  // namespace polydem::geometry
