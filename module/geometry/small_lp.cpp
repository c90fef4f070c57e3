// Dual simplex for  minimise c.z  subject to  A z <= b,  z in R^4 free  (see small_lp.h).
//
// A basis is four linearly independent rows B. Its vertex is z = A_B^-1 b_B and its multipliers
// are y = -A_B^-T c, so that -c = sum_i y_i a_{B_i}. The basis is dual feasible when y >= 0: z then
// minimises c.z over the four half-spaces of B alone, and is optimal once it also satisfies every
// other row. Each pivot brings in a violated row r and drops the basis row l that keeps y >= 0
// (ratio test). This is the primal simplex on the dual  max -b.y s.t. A^T y = -c, y >= 0, with four
// equality rows: a pivot costs one pass over the rows (a 4-term dot product each) and a rank-one
// update of the 4x4 inverse.
//
// Start without a phase one: four artificial box rows s_k z_k <= M with s_k = -sign(c_k) give the
// dual feasible basis y_k = |c_k| for any c. M is symbolic (larger than any number): a right-hand
// side is b0 + M b1 and the vertex z0 + M z1, compared lexicographically, so there is no big-M
// constant to choose and nothing depends on the scale. At the end, a box row still carrying a
// positive multiplier means the objective falls without bound as M grows (unbounded); a violated
// row that no basis row can make room for (no positive ratio-test candidate) proves infeasibility.
// A warm start replaces the box rows by a given basis of real rows that is already dual feasible
// (say the optimal basis of the previous time step): its vertex has no M part, and when the rows
// have moved only a little it is optimal as it stands or a pivot or two away.
//
// Degeneracy (many rows through one vertex, zero multipliers) cannot make the method cycle: the
// most violated row (Dantzig's rule) is taken while pivots make progress, and after a run of
// degenerate pivots Bland's rule (smallest index first, in pricing and in ratio-test ties) takes
// over for the rest of the solve. Both are deterministic. Rows are scaled to unit length first;
// tolerances are then fractions of the problem's size (|z| and the rows' distances from the
// origin), so the same problem in millimetres and in metres takes the same pivots.
#include "polydem/geometry/small_lp.h"

#include <Eigen/LU>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "polydem/core/error.h"
#include "polydem/core/strings.h"

namespace polydem::geometry {
namespace {

using Mat4 = Eigen::Matrix4d;
using Status = SmallLpResult::Status;

/// A row is violated when its excess exceeds this fraction of the problem's size (the largest
/// of |z| and the distances |b_i| / |a_i| of the rows' planes from the origin).
constexpr double kFeasTol = 1e-12;
/// Ratio-test candidates need alpha_i above this fraction of max |alpha|: keeps the basis regular.
constexpr double kPivotTol = 1e-9;
/// Multipliers below this fraction of |c| are zero (rounding of y = -A_B^-T c).
constexpr double kDualTol = 1e-12;
/// Rows held on the stack; larger problems put their working copy on the heap.
constexpr int kStackRows = 64;

/// The working copy of the rows, structure of arrays: rows scaled to unit length (the feasible
/// set does not change, and excesses become distances, comparable between rows), the four box
/// rows appended. Row j is the caller's row j; a zero row (0 <= b with b >= 0) stays as a zero
/// row that is never violated and so never enters a basis.
class RowTable {
 public:
  /// Returns false when a zero row reads 0 <= b < 0 (the problem is infeasible).
  bool load(std::span<const Vec4> rows, std::span<const double> b,
            const std::array<double, 4>& sign);

  int rows() const { return m_; }  // real rows; box row k has index rows() + k
  bool isZero(int j) const { return zero_[j] != 0; }
  double maxAbsB() const { return max_abs_b_; }
  Vec4 row(int j) const { return Vec4(a_[0][j], a_[1][j], a_[2][j], a_[3][j]); }
  double b0(int j) const { return b0_[j]; }  // right-hand side, real part
  double b1(int j) const { return b1_[j]; }  // right-hand side, M part (1 for box rows)
  /// a_j.z - b0_j and a_j.z - b1_j.
  double excess0(int j, const Vec4& z) const { return dot(j, z) - b0_[j]; }
  double excess1(int j, const Vec4& z) const { return dot(j, z) - b1_[j]; }

 private:
  static constexpr int kArrays = 6;
  double dot(int j, const Vec4& z) const {
    return a_[0][j] * z[0] + a_[1][j] * z[1] + a_[2][j] * z[2] + a_[3][j] * z[3];
  }

  std::array<double, kArrays*(kStackRows + 4)> stack_;
  std::array<std::uint8_t, kStackRows + 4> zero_stack_;
  std::array<double*, 4> a_{};
  std::uint8_t* zero_ = nullptr;
  double* b0_ = nullptr;
  double* b1_ = nullptr;
  int m_ = 0;
  double max_abs_b_ = 0.0;
};

// Problems above kStackRows rows use a per-thread buffer that grows once and is then reused, so
// that even they allocate nothing once warm (polydem runs one thread per MPI rank).
struct HeapRows {
  std::vector<double> values;
  std::vector<std::uint8_t> zero;
};
HeapRows& heapRows() {
  thread_local HeapRows heap;
  return heap;
}

bool RowTable::load(std::span<const Vec4> rows, std::span<const double> b,
                    const std::array<double, 4>& sign) {
  const std::size_t stride = rows.size() + 4;
  double* base = stack_.data();
  std::uint8_t* zero = zero_stack_.data();
  if (rows.size() > static_cast<std::size_t>(kStackRows)) {
    HeapRows& heap = heapRows();
    if (heap.values.size() < kArrays * stride) heap.values.resize(kArrays * stride);
    if (heap.zero.size() < stride) heap.zero.resize(stride);
    base = heap.values.data();
    zero = heap.zero.data();
  }
  double* a0 = base;
  double* a1 = base + stride;
  double* a2 = base + 2 * stride;
  double* a3 = base + 3 * stride;
  double* b0 = base + 4 * stride;
  double* b1 = base + 5 * stride;
  const int m = static_cast<int>(rows.size());
  double max_abs_b = 0.0;
  for (int i = 0; i < m; ++i) {
    const Vec4& a = rows[i];
    const double norm = a.norm();
    if (!std::isfinite(norm + b[i])) {
      throw GeometryError(cat("solveSmallLp: row ", i, " is not finite"));
    }
    b1[i] = 0.0;
    zero[i] = norm == 0.0 ? 1 : 0;
    if (zero[i]) {
      if (b[i] < 0.0) return false;
      a0[i] = a1[i] = a2[i] = a3[i] = 0.0;
      b0[i] = b[i];
      continue;
    }
    const double scale = 1.0 / norm;
    a0[i] = a[0] * scale;
    a1[i] = a[1] * scale;
    a2[i] = a[2] * scale;
    a3[i] = a[3] * scale;
    b0[i] = b[i] * scale;
    max_abs_b = std::max(max_abs_b, std::abs(b0[i]));
  }
  a_ = {a0, a1, a2, a3};
  b0_ = b0;
  b1_ = b1;
  zero_ = zero;
  m_ = m;
  max_abs_b_ = max_abs_b;
  for (int k = 0; k < 4; ++k) {  // box row k: sign_k z_k <= M
    for (int i = 0; i < 4; ++i) a_[i][m + k] = i == k ? sign[k] : 0.0;
    b0[m + k] = 0.0;
    b1[m + k] = 1.0;
    zero[m + k] = 0;
  }
  return true;
}

class DualSimplex {
 public:
  DualSimplex(const Vec4& c, const SmallLpOptions& options);
  /// `warm` is null for a cold start, else four row indices to try first.
  SmallLpResult solve(std::span<const Vec4> rows, std::span<const double> b,
                      const std::array<int, 4>* warm);

 private:
  bool isBox(int j) const { return j >= m_; }
  bool inBasis(int j) const {
    return basis_[0] == j || basis_[1] == j || basis_[2] == j || basis_[3] == j;
  }
  void computeVertex();
  int priceFinite(bool bland) const;
  int priceLex(bool bland) const;
  int ratioTest(const Vec4& alpha, bool bland) const;
  void pivot(int r, int l, const Vec4& alpha);
  void refactor();
  void startCold();
  bool startWarm(const std::array<int, 4>& rows);
  SmallLpResult finish();

  SmallLpOptions options_;
  RowTable table_;
  int m_ = 0;  // real rows
  Vec4 c_;
  double c_norm_ = 0.0;
  std::array<double, 4> sign_{};  // s_k of the box row s_k z_k <= M
  std::array<int, 4> basis_{};    // row index per basis position; m + k is box row k
  Mat4 inv_;                      // A_B^-1: A_B * inv_ = I, A_B's rows are the basis rows
  Vec4 y_;                        // multipliers of the basis rows
  Vec4 b0_, b1_;                  // right-hand sides of the basis rows: real part, M part
  Vec4 z0_, z1_;                  // vertex: real part, M part
  int boxes_ = 4;                 // box rows in the basis
};

DualSimplex::DualSimplex(const Vec4& c, const SmallLpOptions& options)
    : options_(options), c_(c), c_norm_(c.norm()) {
  if (!std::isfinite(c_norm_)) throw GeometryError("solveSmallLp: non-finite objective");
  for (int k = 0; k < 4; ++k) sign_[k] = c[k] > 0.0 ? -1.0 : 1.0;
}

void DualSimplex::computeVertex() {
  z0_ = inv_ * b0_;
  z1_ = boxes_ > 0 ? Vec4(inv_ * b1_) : Vec4::Zero();
}

// The entering row once no box row is left: the most violated row (Dantzig) or the first
// violated one (Bland); -1 when z is feasible. Box rows cannot be violated here (z has no M part).
// Basis rows have zero excess up to rounding, far below the tolerance; the scan skips them
// explicitly only if one ever comes out on top.
int DualSimplex::priceFinite(bool bland) const {
  const double tol = kFeasTol * (z0_.cwiseAbs().maxCoeff() + table_.maxAbsB());
  for (const bool skip_basis : {false, true}) {
    double best_excess = tol;
    int best = -1;
    for (int j = 0; j < m_; ++j) {
      const double excess = table_.excess0(j, z0_);
      if (excess > best_excess && !(skip_basis && inBasis(j))) {
        best = j;
        best_excess = excess;
        if (bland) break;
      }
    }
    if (best < 0 || !inBasis(best)) return best;
  }
  return -1;
}

// The same while z = z0 + M z1 has an M part (box rows included). A row's excess is then
// slope * M + excess with slope = a.z1 - b1: the slope decides unless it is zero. Dantzig's rule
// takes the steepest row violated at infinity, else the most violated row of zero slope.
int DualSimplex::priceLex(bool bland) const {
  const int n = m_ + 4;
  const double slope_tol = kFeasTol * (z1_.cwiseAbs().maxCoeff() + 1.0);
  const double excess_tol = kFeasTol * (z0_.cwiseAbs().maxCoeff() + table_.maxAbsB());
  auto violated = [&](int j) {
    const double slope = table_.excess1(j, z1_);
    return slope > slope_tol || (slope >= -slope_tol && table_.excess0(j, z0_) > excess_tol);
  };
  for (const bool skip_basis : {false, true}) {
    int best = -1;
    if (bland) {
      for (int j = 0; j < n && best < 0; ++j) {
        if (violated(j) && !(skip_basis && inBasis(j))) best = j;
      }
    } else {
      double best_slope = slope_tol;
      for (int j = 0; j < n; ++j) {
        const double slope = table_.excess1(j, z1_);
        if (slope > best_slope && !(skip_basis && inBasis(j))) {
          best = j;
          best_slope = slope;
        }
      }
      if (best < 0) {  // nothing violated at infinity: the real parts of zero-slope rows decide
        double best_excess = excess_tol;
        for (int j = 0; j < n; ++j) {
          if (table_.excess1(j, z1_) < -slope_tol) continue;
          const double excess = table_.excess0(j, z0_);
          if (excess > best_excess && !(skip_basis && inBasis(j))) {
            best = j;
            best_excess = excess;
          }
        }
      }
    }
    if (best < 0 || !inBasis(best)) return best;
  }
  return -1;
}

// The leaving basis position: minimises y_i / alpha_i over alpha_i > 0, or -1 when no alpha_i is
// positive. Ties (typically several zero multipliers) go to the largest alpha_i for a
// well-conditioned basis, or to the lowest row index under Bland's rule.
int DualSimplex::ratioTest(const Vec4& alpha, bool bland) const {
  const double threshold = kPivotTol * alpha.cwiseAbs().maxCoeff();
  int leave = -1;
  for (int i = 0; i < 4; ++i) {
    if (!(alpha[i] > threshold)) continue;
    if (leave < 0) {
      leave = i;
      continue;
    }
    // Compare y_i / alpha_i with y_l / alpha_l without dividing (both alphas are positive).
    const double lhs = y_[i] * alpha[leave];
    const double rhs = y_[leave] * alpha[i];
    if (lhs < rhs) {
      leave = i;
    } else if (lhs == rhs) {
      const bool better = bland ? basis_[i] < basis_[leave] : alpha[i] > alpha[leave];
      if (better) leave = i;
    }
  }
  return leave;
}

// Row r replaces basis position l: a_r = sum_i alpha_i a_{B_i}, so the multipliers move by
// -t alpha with t = y_l / alpha_l, and the inverse gets the matching column operations.
void DualSimplex::pivot(int r, int l, const Vec4& alpha) {
  const double t = y_[l] / alpha[l];
  const double zero = kDualTol * c_norm_;
  inv_.col(l) *= 1.0 / alpha[l];
  for (int i = 0; i < 4; ++i) {
    if (i == l) continue;
    inv_.col(i) -= alpha[i] * inv_.col(l);
    const double yi = y_[i] - t * alpha[i];
    y_[i] = yi > zero ? yi : 0.0;
  }
  y_[l] = t;
  if (isBox(basis_[l])) --boxes_;
  if (isBox(r)) ++boxes_;
  basis_[l] = r;
  b0_[l] = table_.b0(r);
  b1_[l] = table_.b1(r);
}

// Recomputes the inverse and the multipliers from the basis rows, shedding the rounding that
// rank-one updates accumulate.
void DualSimplex::refactor() {
  Mat4 a_b;
  for (int i = 0; i < 4; ++i) a_b.row(i) = table_.row(basis_[i]).transpose();
  inv_ = a_b.partialPivLu().inverse();
  const Vec4 y = -(inv_.transpose() * c_);
  const double zero = kDualTol * c_norm_;
  for (int i = 0; i < 4; ++i) y_[i] = y[i] > zero ? y[i] : 0.0;
}

// The artificial start: the four box rows, dual feasible for any c.
void DualSimplex::startCold() {
  inv_.setZero();
  for (int k = 0; k < 4; ++k) {
    basis_[k] = m_ + k;
    inv_(k, k) = sign_[k];
    y_[k] = std::abs(c_[k]);
  }
  b0_.setZero();
  b1_.setOnes();
  boxes_ = 4;
}

// A given basis of real rows: usable when they are distinct non-zero rows, A_B is well
// conditioned (the rows have unit length, so |det A_B| >= kWarmDet bounds the smallest singular
// value from below by kWarmDet / 8) and the multipliers y = -A_B^-T c are >= 0 up to rounding.
bool DualSimplex::startWarm(const std::array<int, 4>& rows) {
  constexpr double kWarmDet = 1e-8;
  for (int i = 0; i < 4; ++i) {
    if (rows[i] < 0 || rows[i] >= m_ || table_.isZero(rows[i])) return false;
    for (int k = 0; k < i; ++k) {
      if (rows[k] == rows[i]) return false;
    }
  }
  Mat4 a_b;
  for (int i = 0; i < 4; ++i) a_b.row(i) = table_.row(rows[i]).transpose();
  Mat4 inv;
  double det = 0.0;
  bool invertible = false;
  a_b.computeInverseAndDetWithCheck(inv, det, invertible, kWarmDet);
  if (!invertible || !inv.allFinite()) return false;
  const Vec4 y = -(inv.transpose() * c_);
  const double zero = kDualTol * c_norm_;
  for (int i = 0; i < 4; ++i) {
    if (y[i] < -zero) return false;
  }
  inv_ = inv;
  for (int i = 0; i < 4; ++i) {
    basis_[i] = rows[i];
    y_[i] = y[i] > zero ? y[i] : 0.0;
    b0_[i] = table_.b0(rows[i]);
    b1_[i] = 0.0;
  }
  boxes_ = 0;
  return true;
}

SmallLpResult DualSimplex::solve(std::span<const Vec4> rows, std::span<const double> b,
                                 const std::array<int, 4>* warm) {
  if (b.size() != rows.size()) {
    throw Error(cat("solveSmallLp: ", rows.size(), " rows but ", b.size(), " right-hand sides"));
  }
  SmallLpResult result;
  result.status = Status::kInfeasible;
  if (!table_.load(rows, b, sign_)) return result;
  m_ = table_.rows();
  if (warm == nullptr || !startWarm(*warm)) startCold();

  const int max_pivots = 64 * (m_ + 4);
  int degenerate_run = 0, since_refactor = 0, pivots = 0;
  bool bland = options_.bland_after <= 0;
  for (;;) {
    computeVertex();
    const int r = boxes_ > 0 ? priceLex(bland) : priceFinite(bland);
    if (r < 0) break;
    if (pivots == max_pivots) {
      throw GeometryError(cat("solveSmallLp: no convergence after ", pivots, " pivots on ", m_,
                              " rows; the rows are numerically degenerate"));
    }
    const Vec4 alpha = inv_.transpose() * table_.row(r);
    const int l = ratioTest(alpha, bland);
    if (l < 0) {  // no basis row can make room for row r: a proof of infeasibility
      result.iterations = pivots;
      return result;
    }
    degenerate_run = y_[l] == 0.0 ? degenerate_run + 1 : 0;
    if (degenerate_run >= options_.bland_after) bland = true;
    pivot(r, l, alpha);
    ++pivots;
    if (++since_refactor >= options_.refactor_every) {
      refactor();
      since_refactor = 0;
    }
  }
  result = finish();
  result.iterations = pivots;
  return result;
}

SmallLpResult DualSimplex::finish() {
  SmallLpResult result;
  for (int i = 0; i < 4; ++i) {
    if (isBox(basis_[i]) && y_[i] > 0.0) {
      result.status = Status::kUnbounded;
      return result;
    }
  }
  // One step of iterative refinement: the vertex to the accuracy of a fresh solve.
  Mat4 a_b;
  for (int i = 0; i < 4; ++i) a_b.row(i) = table_.row(basis_[i]).transpose();
  z0_ += inv_ * (b0_ - a_b * z0_);
  Vec4 z = z0_;
  if (boxes_ > 0) {
    // The optimum is not unique: the optimal set holds the ray z0 + t z1 (t -> infinity) and
    // c.z1 = 0. Rows with a.z1 < 0 may still cut z0 itself; walk out just far enough.
    z1_ += inv_ * (b1_ - a_b * z1_);
    const double slope_tol = kFeasTol * z1_.cwiseAbs().maxCoeff();
    double t = 0.0;
    for (int j = 0; j < m_; ++j) {
      const double slope = table_.excess1(j, z1_);
      const double excess = table_.excess0(j, z0_);
      if (slope < -slope_tol && excess > 0.0) t = std::max(t, excess / -slope);
    }
    z += t * z1_;
  }
  result.status = Status::kOptimal;
  result.z = z;
  result.objective = c_.dot(z);
  for (int i = 0; i < 4; ++i) {
    result.basis[i] = isBox(basis_[i]) ? -1 : basis_[i];
    result.multipliers[i] = y_[i];
  }
  return result;
}

}  // namespace

SmallLpResult solveSmallLp(std::span<const Vec4> rows, std::span<const double> b, const Vec4& c,
                           const SmallLpOptions& options) {
  return DualSimplex(c, options).solve(rows, b, nullptr);
}

SmallLpResult solveSmallLp(std::span<const Vec4> rows, std::span<const double> b, const Vec4& c) {
  return solveSmallLp(rows, b, c, SmallLpOptions{});
}

SmallLpResult solveSmallLp(std::span<const Vec4> rows, std::span<const double> b, const Vec4& c,
                           const std::array<int, 4>& basis, const SmallLpOptions& options) {
  return DualSimplex(c, options).solve(rows, b, &basis);
}

}  // namespace polydem::geometry
