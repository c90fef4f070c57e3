// Newton's method for the analytic centre (see analytic_centre.h).
//
// With q_i = 1 / s_i and u_i = q_i a_i, the gradient and Hessian of phi are
//   g = sum_i u_i,   H = sum_i u_i u_i^T,
// the Newton step is D = -H^-1 g and the Newton decrement lambda^2 = g^T H^-1 g = -g . D.
// Along the step the slacks fall linearly, s_i(x + t D) = s_i (1 - t w_i) with w_i = q_i a_i . D,
// so the barrier's change is exactly  phi(x + t D) - phi(x) = -log prod_i (1 - t w_i)  and the
// Armijo test needs one logarithm per trial, not one per plane.
//
// Two facts from self-concordance (Boyd & Vandenberghe section 9.6) spare work near the centre:
// sum_i w_i^2 = D^T H D = lambda^2, so for lambda < 1 every w_i < 1 and the full step stays
// inside; and for lambda <= (1 - 2 alpha) / 4 backtracking accepts t = 1 anyway, so the line
// search is skipped there.
//
// Thin sets make H ill-conditioned (eigenvalues ~ 1/width^2 across, ~ 1/extent^2 along). The
// closed-form L D L^T factorisation is accurate while its pivots keep more than 1e-12 of the
// diagonal; below, the step is taken from a QR factorisation of the m x 3 matrix J with rows u_i
// (H = J^T J, g = J^T 1: D solves min |J D + 1|), whose condition number is only the square root
// of H's. Once lambda is small, a decrement that stops halving shows that round-off, not the
// iteration, limits it: the point is then as good as the arithmetic allows.
#include "polydem/geometry/analytic_centre.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace polydem::geometry {
namespace {

/// L D L^T pivots must keep this fraction of their diagonal entry (else QR takes over).
constexpr double kPivotKeep = 1e-12;
/// Below this decrement a decrement that does not halve is taken as the round-off floor.
constexpr double kNoiseDecrement = 1e-3;
/// Renormalise the running product of the line search every this many factors.
constexpr int kProductBlock = 8;
/// Bound on the line search's halvings (t = 0.5^60 ~ 1e-18 moves nothing).
constexpr int kMaxBacktracks = 60;

/// The exact line search stops once the 1-D Newton decrement is below this (phi is then within
/// about its square of the minimum along the line) or after kMaxLineNewton steps.
constexpr double kLineDecrement = 0.05;
constexpr int kMaxLineNewton = 12;

struct Scratch {
  std::vector<double> q;              // 1 / s_i
  std::vector<double> w;              // q_i a_i . D: rate of fall of slack i along the step
  std::vector<double> j0, j1, j2, r;  // QR fallback: columns of J and the right-hand side
};
Scratch& scratch() {
  thread_local Scratch s;
  return s;
}

/// H = L D L^T with L unit lower triangular (no square roots: the dependency chain per Newton
/// step is three reciprocals); D = -H^-1 g and lambda^2 = g^T H^-1 g = sum_k y_k^2 / d_k with
/// y = L^-1 g. Returns false when a pivot d_k keeps less than kPivotKeep of its diagonal entry.
bool ldltStep(const double h[6], const Vec3& g, Vec3& step, double& lambda2) {
  // h = {h00, h10, h11, h20, h21, h22}
  if (!(h[0] > 0.0)) return false;
  const double inv0 = 1.0 / h[0];
  const double l10 = h[1] * inv0;
  const double l20 = h[3] * inv0;
  const double d1 = h[2] - l10 * h[1];
  if (!(d1 > kPivotKeep * h[2])) return false;
  const double inv1 = 1.0 / d1;
  const double l21 = (h[4] - l20 * h[1]) * inv1;
  const double d2 = h[5] - l20 * h[3] - l21 * l21 * d1;
  if (!(d2 > kPivotKeep * h[5])) return false;
  const double inv2 = 1.0 / d2;
  const double y0 = -g.x();
  const double y1 = -g.y() - l10 * y0;
  const double y2 = -g.z() - l20 * y0 - l21 * y1;
  lambda2 = y0 * y0 * inv0 + y1 * y1 * inv1 + y2 * y2 * inv2;
  step.z() = y2 * inv2;
  step.y() = y1 * inv1 - l21 * step.z();
  step.x() = y0 * inv0 - l10 * step.y() - l20 * step.z();
  return std::isfinite(lambda2) && step.allFinite();
}

double dot(const std::vector<double>& u, const std::vector<double>& v, int m) {
  double sum = 0.0;
  for (int i = 0; i < m; ++i) sum += u[i] * v[i];
  return sum;
}
void subtract(std::vector<double>& u, double f, const std::vector<double>& v, int m) {
  for (int i = 0; i < m; ++i) u[i] -= f * v[i];
}
// Normalises column u in place; returns its former length (0 if it had none).
double normalise(std::vector<double>& u, int m) {
  const double length = std::sqrt(dot(u, u, m));
  if (length > 0.0) {
    const double inv = 1.0 / length;
    for (int i = 0; i < m; ++i) u[i] *= inv;
  }
  return length;
}

/// The Newton step from modified Gram-Schmidt on the augmented matrix [J | -1] (backward stable
/// for least squares; Bjorck, Numerical Methods for Least Squares Problems, 1996, section 2.4.3).
bool qrStep(const Halfspaces& h, const std::vector<double>& q, Vec3& step, double& lambda2) {
  const int m = h.size();
  Scratch& s = scratch();
  s.j0.resize(m);
  s.j1.resize(m);
  s.j2.resize(m);
  s.r.resize(m);
  for (int i = 0; i < m; ++i) {
    s.j0[i] = h.ax()[i] * q[i];
    s.j1[i] = h.ay()[i] * q[i];
    s.j2[i] = h.az()[i] * q[i];
    s.r[i] = -1.0;
  }
  const double scale = std::max({std::sqrt(dot(s.j0, s.j0, m)), std::sqrt(dot(s.j1, s.j1, m)),
                                 std::sqrt(dot(s.j2, s.j2, m))});
  const double tiny = std::numeric_limits<double>::epsilon() * scale;
  const double r00 = normalise(s.j0, m);
  if (!(r00 > tiny)) return false;
  const double r01 = dot(s.j0, s.j1, m), r02 = dot(s.j0, s.j2, m), c0 = dot(s.j0, s.r, m);
  subtract(s.j1, r01, s.j0, m);
  subtract(s.j2, r02, s.j0, m);
  subtract(s.r, c0, s.j0, m);
  const double r11 = normalise(s.j1, m);
  if (!(r11 > tiny)) return false;
  const double r12 = dot(s.j1, s.j2, m), c1 = dot(s.j1, s.r, m);
  subtract(s.j2, r12, s.j1, m);
  subtract(s.r, c1, s.j1, m);
  const double r22 = normalise(s.j2, m);
  if (!(r22 > tiny)) return false;
  const double c2 = dot(s.j2, s.r, m);
  lambda2 = c0 * c0 + c1 * c1 + c2 * c2;
  step.z() = c2 / r22;
  step.y() = (c1 - r12 * step.z()) / r11;
  step.x() = (c0 - r01 * step.y() - r02 * step.z()) / r00;
  return std::isfinite(lambda2) && step.allFinite();
}

/// log prod_i (1 - t w_i), or -infinity when a factor is not positive: one logarithm for all
/// the factors, their product kept in range by moving its exponent out every few factors.
double logProduct(const std::vector<double>& w, int m, double t) {
  double mantissa = 1.0;
  int exponent = 0;
  for (int i = 0; i < m; ++i) {
    const double factor = 1.0 - t * w[i];
    if (!(factor > 0.0)) return -std::numeric_limits<double>::infinity();
    mantissa *= factor;
    if (i % kProductBlock == kProductBlock - 1) {
      int e = 0;
      mantissa = std::frexp(mantissa, &e);
      exponent += e;
    }
  }
  return std::log(mantissa) + exponent * std::log(2.0);
}

/// w_i = q_i a_i . D and the chord lo < t < hi of the set along D (1 - t w_i > 0 for all i):
/// hi = 1 / max w_i over w_i > 0, lo = 1 / min w_i over w_i < 0.
void slopes(const Halfspaces& h, const std::vector<double>& q, const Vec3& step,
            std::vector<double>& w, double& lo, double& hi) {
  const double* ax = h.ax();
  const double* ay = h.ay();
  const double* az = h.az();
  double largest = 0.0, smallest = 0.0;
  for (int i = 0; i < h.size(); ++i) {
    const double wi = q[i] * (ax[i] * step.x() + ay[i] * step.y() + az[i] * step.z());
    w[i] = wi;
    largest = std::max(largest, wi);
    smallest = std::min(smallest, wi);
  }
  constexpr double kInf = std::numeric_limits<double>::infinity();
  hi = largest > 0.0 ? 1.0 / largest : kInf;
  lo = smallest < 0.0 ? 1.0 / smallest : -kInf;
}

/// The Armijo step (B&V algorithm 9.2): the largest t = beta^k with
/// phi(x + t D) <= phi(x) - alpha t lambda^2, i.e. log prod_i (1 - t w_i) >= alpha t lambda^2.
double backtrack(const std::vector<double>& w, int m, double lambda2,
                 const AnalyticCentreOptions& options) {
  double t = 1.0;
  for (int k = 0; k < kMaxBacktracks; ++k) {
    if (logProduct(w, m, t) >= options.alpha * t * lambda2) break;
    t *= options.beta;
  }
  return t;
}

/// The minimiser of psi(t) = phi(x + t D) - phi(x) = -sum_i log(1 - t w_i) over the chord
/// lo < t < hi of the set along D. psi is convex with psi' = sum w_i / (1 - t w_i) rising from
/// -inf to +inf across the chord; 1-D Newton steps are kept inside a bracket of the root of psi'
/// and replaced by bisection when they leave it. The start is t = 1 (the Newton step) when
/// lambda < 1, where the full step is inside and near the minimiser, else the chord's middle.
/// Returns 0 if no point with psi < 0 was found (the caller then backtracks).
double exactStep(const std::vector<double>& w, int m, double lo, double hi, double lambda) {
  if (!std::isfinite(lo) || !std::isfinite(hi)) return 0.0;  // unbounded along D
  double t = lambda < 1.0 ? 1.0 : 0.5 * (lo + hi);
  for (int k = 0; k < kMaxLineNewton; ++k) {
    double d1 = 0.0, d2 = 0.0;
    for (int i = 0; i < m; ++i) {
      const double r = w[i] / (1.0 - t * w[i]);
      d1 += r;
      d2 += r * r;
    }
    if (d1 > 0.0) {
      hi = t;
    } else {
      lo = t;
    }
    if (d1 * d1 <= kLineDecrement * kLineDecrement * d2) break;
    const double next = t - d1 / d2;
    t = next > lo && next < hi ? next : 0.5 * (lo + hi);
  }
  return logProduct(w, m, t) > 0.0 ? t : 0.0;
}

}  // namespace

Vec3 barrierGradient(const Halfspaces& h, const Vec3& x) {
  Vec3 g = Vec3::Zero();
  for (int i = 0; i < h.size(); ++i) g += h.normal(i) / h.slack(i, x);
  return g;
}

AnalyticCentreResult analyticCentre(const Halfspaces& h, const Vec3& start,
                                    const AnalyticCentreOptions& options) {
  const int m = h.size();
  AnalyticCentreResult result;
  result.x = start;
  std::vector<double>& q = scratch().q;
  q.resize(m);
  scratch().w.resize(m);
  const double* ax = h.ax();
  const double* ay = h.ay();
  const double* az = h.az();
  const double* d = h.d();
  // B&V section 9.6.4: backtracking accepts the full step when lambda <= (1 - 2 alpha) / 4.
  const double full_step_decrement = (1.0 - 2.0 * options.alpha) / 4.0;
  double previous = std::numeric_limits<double>::infinity();
  Vec3 x = start;
  for (int iteration = 0; iteration < options.max_iterations; ++iteration) {
    double g0 = 0.0, g1 = 0.0, g2 = 0.0;
    double h00 = 0.0, h10 = 0.0, h11 = 0.0, h20 = 0.0, h21 = 0.0, h22 = 0.0;
    const double margin = iteration == 0 ? options.start_margin : 0.0;
    bool inside = true;
    for (int i = 0; i < m; ++i) {
      const double s = d[i] - (ax[i] * x.x() + ay[i] * x.y() + az[i] * x.z());
      inside = inside && s > margin;
      const double qi = 1.0 / s;
      q[i] = qi;
      const double u0 = ax[i] * qi, u1 = ay[i] * qi, u2 = az[i] * qi;
      g0 += u0;
      g1 += u1;
      g2 += u2;
      h00 += u0 * u0;
      h10 += u1 * u0;
      h11 += u1 * u1;
      h20 += u2 * u0;
      h21 += u2 * u1;
      h22 += u2 * u2;
    }
    if (!inside) {
      // At the start: rejected. Later: round-off put the last step on a plane; keep the one before.
      result.start_rejected = iteration == 0;
      return result;
    }
    result.x = x;
    const double hessian[6] = {h00, h10, h11, h20, h21, h22};
    const Vec3 g(g0, g1, g2);
    Vec3 step;
    double lambda2 = 0.0;
    if (!ldltStep(hessian, g, step, lambda2) && !qrStep(h, q, step, lambda2)) return result;
    const double lambda = std::sqrt(lambda2);
    result.decrement = lambda;
    const bool last =
        lambda <= options.decrement_tol || (lambda <= kNoiseDecrement && lambda > 0.5 * previous);
    double t = 1.0;
    if (lambda > full_step_decrement) {
      std::vector<double>& w = scratch().w;
      double lo = 0.0, hi = 0.0;
      slopes(h, q, step, w, lo, hi);
      t = options.line_search == AnalyticCentreOptions::LineSearch::kExact
              ? exactStep(w, m, lo, hi, lambda)
              : 0.0;
      if (t == 0.0) t = backtrack(w, m, lambda2, options);
    }
    x += t * step;
    result.iterations = iteration + 1;
    previous = lambda;
    if (last) {
      // A full step with lambda < 1 keeps every slack above (1 - lambda) of its value (the Dikin
      // ellipsoid is inside), so the last point needs no check.
      result.x = x;
      result.converged = true;
      return result;
    }
  }
  if (h.minSlack(x) > 0.0) result.x = x;
  return result;
}

}  // namespace polydem::geometry
