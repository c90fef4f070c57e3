// The analytic centre of a bounded set of half-spaces a_i . x <= d_i: the point that maximises
// sum_i log(d_i - a_i . x), i.e. minimises the log barrier
//   phi(x) = -sum_i log s_i(x),   s_i(x) = d_i - a_i . x,
// found by Newton's method with a backtracking line search (Boyd & Vandenberghe, Convex
// Optimization, 2004: section 8.5.3 for the analytic centre, algorithms 9.2 and 9.5 for the
// line search and Newton's method). Boon et al. (2012) take it as the contact point of two
// potential blocks (module/contact/potential/lp.h).
//
// The barrier is self-concordant and Newton's method is affine invariant: the iteration count
// and the stopping test (on the Newton decrement lambda, which has no unit) do not depend on the
// unit of length, on the pose, or on how thin the set is. Cost per iteration: one pass over the
// planes for the gradient and the 3x3 Hessian, a closed-form 3x3 L D L^T factorisation, and, in
// the damped phase only, a few more passes for the line search. No heap allocation once warm.
#pragma once

#include "polydem/core/types.h"
#include "polydem/geometry/halfspaces.h"

namespace polydem::geometry {

struct AnalyticCentreOptions {
  /// Bound on Newton iterations; reaching it returns the last iterate with converged = false.
  int max_iterations = 60;
  /// The last step is taken once lambda falls below this: Newton's quadratic convergence then
  /// leaves a decrement of about its square (1e-12), i.e. the centre to about 1e-12 of the
  /// set's extent in every direction.
  double decrement_tol = 1e-6;
  /// How the step length is chosen while lambda is large (near the centre the full step is
  /// taken either way). kBacktracking: B&V algorithm 9.2 from t = 1. kExact: the minimiser of
  /// phi along the Newton direction (B&V section 9.2, "exact line search"), by safeguarded 1-D
  /// Newton steps inside the chord of the set; from a point near a face, where the full step
  /// only doubles the distance to that face, it reaches the middle of the chord in one step.
  enum class LineSearch { kExact, kBacktracking };
  LineSearch line_search = LineSearch::kExact;
  /// Backtracking (Armijo) parameters alpha and beta (B&V algorithm 9.2); kExact falls back to
  /// backtracking should its 1-D search fail to decrease phi.
  double alpha = 0.1;
  double beta = 0.5;
  /// The start is used only if every slack there exceeds this (a length >= 0); otherwise the
  /// result says start_rejected and nothing is iterated. Lets a caller try a guess (the last
  /// centre) at the price of no extra pass over the planes.
  double start_margin = 0.0;
};

struct AnalyticCentreResult {
  Vec3 x = Vec3::Zero();
  int iterations = 0;      // Newton steps taken
  double decrement = 0.0;  // lambda = sqrt(g^T H^-1 g) at the last point where it was computed
  bool converged = false;
  bool start_rejected = false;  // a slack at the start was <= options.start_margin
};

/// The analytic centre of `h` (bounded, with a non-empty interior), started from `start`, which
/// must lie strictly inside every plane, by more than options.start_margin (else
/// start_rejected). Returns converged = false, with the best point reached, when the bound on
/// iterations is hit or the Hessian is numerically singular (an unbounded set).
AnalyticCentreResult analyticCentre(const Halfspaces& h, const Vec3& start,
                                    const AnalyticCentreOptions& options = {});

/// The gradient of phi at x: sum_i a_i / s_i(x) (zero at the centre).
Vec3 barrierGradient(const Halfspaces& h, const Vec3& x);

}  // namespace polydem::geometry
