// Kernel "lp" (see lp.h and docs/kernels/lp.md).
//
// Order of work in collide(), cheapest first: bounding spheres apart -> not touching; the last
// separating direction (PairState) still separates the vertices -> not touching; planes of both
// blocks in A's frame; a point strictly inside both (which proves s* < 0 without the LP): the last
// contact point, else the middle of the overlap's chord along the line of centres; if the chord
// is empty, the line of centres may separate the vertices -> not touching; else the LP decides
// and gives the point. Newton's method then finds the analytic centre, the two potential
// particles the normal, the planes the chord.
//
// LpScratch: the planes of a pair, the LP rows and the slacks at the contact point live in
// thread_local buffers (polydem runs one thread per MPI rank) that keep their capacity, so
// collide() allocates nothing once warm.
//
// PairState: the last contact point is kept in both bodies' frames, warm_point in A's and
// warm_direction in B's; the guess is the mean of the two, which moves with the overlap (to first
// order, a mid-plane between faces of A and B moves by the mean of their motions). The LP's last
// optimal basis is packed into `reserved` (four 8-bit indices into A's faces followed by B's; only
// pairs with at most 256 faces in all). A pair found apart keeps a separating direction (the
// line of centres, or the LP dual's) in warm_direction, in A's frame. warm_valid says which of
// these hold (kWarmPoint, kWarmBasis, kWarmAxis).
#include "polydem/contact/potential/lp.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <vector>

#include "polydem/contact/kernel_factories.h"
#include "polydem/core/error.h"
#include "polydem/core/strings.h"
#include "polydem/geometry/analytic_centre.h"
#include "polydem/geometry/small_lp.h"

namespace polydem::contact {
namespace {

using geometry::Halfspaces;
using geometry::Vec4;

/// The pair touches iff the LP's optimum s* < -kTouch * (r_A + r_B) (circumradii): a pair whose
/// faces merely touch (s* = 0 up to round-off) does not.
constexpr double kTouch = 1e-12;
/// Faces whose slack exceeds the smallest by less than this fraction of r count as equally near.
constexpr double kTieRel = 1e-12;
/// |g_B - g_A| below this (the two unit normals agree): the normal falls back (kDegenerate).
constexpr double kOpposedMin = 1e-6;

constexpr std::uint32_t kWarmPoint = 1u;
constexpr std::uint32_t kWarmBasis = 2u;
constexpr std::uint32_t kWarmAxis = 4u;
constexpr int kMaxPackedRows = 256;

struct LpScratch {
  Halfspaces faces;
  std::vector<Vec4> rows;
  std::vector<double> rhs;
  std::vector<double> slack;  // d_i - a_i . x at the contact point
};
LpScratch& lpScratch() {
  thread_local LpScratch s;
  return s;
}

LpKernel::Trace& trace() {
  thread_local LpKernel::Trace t;
  return t;
}

/// The pair in A's body frame, with the origin moved to the midpoint of the two centroids so
/// that plane offsets are of the pair's size wherever the pair is.
struct PairFrame {
  Mat3 rotation;  // B's body frame to A's: R_A^T R_B
  Vec3 position;  // B's body origin in A's frame: R_A^T (p_B - p_A)
  Vec3 origin;    // the midpoint of the centroids in A's frame
  Vec3 centre_a, centre_b;
  PairFrame(const Body& a, const Body& b)
      : rotation(a.rotation.transpose() * b.rotation),
        position(a.rotation.transpose() * (b.position - a.position)),
        centre_a(a.shape->centroid()),
        centre_b(position + rotation * b.shape->centroid()) {
    origin = 0.5 * (centre_a + centre_b);
  }
  Vec3 fromB(const Vec3& y) const { return position + rotation * y; }
  Vec3 toB(const Vec3& y) const { return rotation.transpose() * (y - position); }
};

/// The faces of A and then of B as planes a . x <= d in the pair frame (x relative to the
/// origin): A's face n . y <= o as n . x <= o - n . origin; B's face n . z <= o, z = toB(y), as
/// (R n) . x <= o + (R n) . (position - origin).
void placeFaces(const Body& a, const Body& b, const PairFrame& frame, Halfspaces& faces) {
  int i = 0;
  for (const auto& face : a.shape->faces()) {
    faces.set(i++, face.normal, face.offset - face.normal.dot(frame.origin));
  }
  const Vec3 shift = frame.position - frame.origin;
  for (const auto& face : b.shape->faces()) {
    const Vec3 n = frame.rotation * face.normal;
    faces.set(i++, n, face.offset + n.dot(shift));
  }
}

/// The unit outward normal of one block's inner potential particle (see innerPotentialNormal),
/// from the slacks s_i of its planes [begin, end) at the point.
Vec3 unitOutward(const Halfspaces& faces, const double* slack, int begin, int end, double r) {
  Vec3 g = Vec3::Zero();
  double nearest = std::numeric_limits<double>::infinity();
  for (int i = begin; i < end; ++i) {
    const double w = r - slack[i];  // a_i . x - d_i + r; grad f = 2 sum <w_i> a_i
    if (w > 0.0) g += w * faces.normal(i);
    nearest = std::min(nearest, slack[i]);
  }
  const double length = g.norm();
  if (length > 0.0) return g / length;
  // grad f_r = 2 sum_i <r - s_i> a_i: as r grows past the smallest slack, only the nearest
  // faces have weight, so the direction tends to the sum of their normals.
  Vec3 sum = Vec3::Zero();
  for (int i = begin; i < end; ++i) {
    if (slack[i] - nearest <= kTieRel * r) sum += faces.normal(i);
  }
  const double sum_length = sum.norm();
  return sum_length > 0.0 ? Vec3(sum / sum_length) : Vec3::Zero();
}

/// Whether the vertices of A and B are apart along w by more than `gap` times |w|.
bool separatedAlong(const Body& a, const Body& b, const Vec3& w, double gap) {
  double top_a = -std::numeric_limits<double>::infinity();
  for (const Vec3& v : a.vertices) top_a = std::max(top_a, w.dot(v));
  double bottom_b = std::numeric_limits<double>::infinity();
  for (const Vec3& v : b.vertices) bottom_b = std::min(bottom_b, w.dot(v));
  return bottom_b - top_a > gap * w.norm();
}

/// The separating direction of the LP's dual when s* > 0: with y the multipliers of the optimal
/// basis, sum_k y_k a_k = 0 and sum_k y_k d_k = -s* sqrt(2) (rows (a, -1) at unit length), so
/// w = sum over A's basis rows of y_k a_k has w . x <= sum_A y_k d_k on A and w . x >= -sum_B y_k
/// d_k on B: the blocks lie on either side of a slab of width s* sqrt(2) / |w| across w.
Vec3 dualSeparatingAxis(const geometry::SmallLpResult& lp, const Halfspaces& faces, int na) {
  Vec3 w = Vec3::Zero();
  for (int k = 0; k < 4; ++k) {
    if (lp.basis[k] >= 0 && lp.basis[k] < na) w += lp.multipliers[k] * faces.normal(lp.basis[k]);
  }
  return w;
}

std::uint32_t packBasis(const std::array<int, 4>& basis) {
  std::uint32_t packed = 0;
  for (int k = 0; k < 4; ++k) packed |= static_cast<std::uint32_t>(basis[k]) << (8 * k);
  return packed;
}
std::array<int, 4> unpackBasis(std::uint32_t packed) {
  std::array<int, 4> basis{};
  for (int k = 0; k < 4; ++k) basis[k] = static_cast<int>((packed >> (8 * k)) & 0xffu);
  return basis;
}

// Boon et al. (2012): minimise s s.t. a_i . x - s <= d_i over both blocks' faces. Returns the
// LP's point when s* < -touch (the blocks overlap), else nothing, keeping the optimal basis and
// the dual's separating direction in `state`.
std::optional<Vec3> overlapLp(LpScratch& s, int na, double touch, particles::PairState* state) {
  const int n = s.faces.size();
  LpKernel::Trace& tr = trace();
  s.rows.resize(n);
  s.rhs.resize(n);
  for (int i = 0; i < n; ++i) {
    s.rows[i] = Vec4(s.faces.ax()[i], s.faces.ay()[i], s.faces.az()[i], -1.0);
    s.rhs[i] = s.faces.d()[i];
  }
  const Vec4 objective(0.0, 0.0, 0.0, 1.0);
  const bool warm_basis = state != nullptr && (state->warm_valid & kWarmBasis) != 0;
  const geometry::SmallLpResult lp =
      warm_basis ? geometry::solveSmallLp(s.rows, s.rhs, objective, unpackBasis(state->reserved))
                 : geometry::solveSmallLp(s.rows, s.rhs, objective);
  tr.lp_solved = true;
  tr.lp_warm_basis = warm_basis;
  tr.lp_pivots = lp.iterations;
  if (lp.status != geometry::SmallLpResult::Status::kOptimal) {
    // Both blocks are bounded and non-empty: the LP is feasible (s large) and bounded below.
    throw GeometryError(cat("lp kernel: the overlap LP of a pair of blocks with ", na, " and ",
                            n - na, " faces has no optimum"));
  }
  tr.lp_objective = lp.z[3];
  if (state != nullptr) {
    const bool packable =
        n <= kMaxPackedRows && *std::min_element(lp.basis.begin(), lp.basis.end()) >= 0;
    state->warm_valid =
        packable ? (state->warm_valid | kWarmBasis) : (state->warm_valid & ~kWarmBasis);
    state->reserved = packable ? packBasis(lp.basis) : 0u;
  }
  if (lp.z[3] < -touch) return Vec3(lp.z.head<3>());
  if (state != nullptr) {
    // Keep the dual's separating direction (A's frame) for a cheap test next time.
    const Vec3 w = dualSeparatingAxis(lp, s.faces, na);
    state->warm_valid &= ~(kWarmPoint | kWarmAxis);
    if (w.norm() > 0.0) {
      state->warm_direction = w;
      state->warm_valid |= kWarmAxis;
    }
  }
  return std::nullopt;
}

// Boon et al. (2012): the contact point is the analytic centre of the overlap, by Newton's method
// from a point strictly inside both blocks: the last centre if it still is, else the middle of
// the overlap's chord along the line of centres if there is one, else the LP's point. Returns
// start_rejected when the blocks are apart: the line of centres separates their vertices (tried
// when it misses the overlap, before the LP) or the LP says so.
geometry::AnalyticCentreResult contactCentre(const Body& a, const Body& b, const PairFrame& frame,
                                             LpScratch& s, int na, double touch,
                                             particles::PairState* state) {
  LpKernel::Trace& tr = trace();
  geometry::AnalyticCentreOptions newton;
  newton.start_margin = touch;
  geometry::AnalyticCentreResult centre;
  centre.start_rejected = true;
  if (state != nullptr && (state->warm_valid & kWarmPoint) != 0) {
    const Vec3 guess = 0.5 * (state->warm_point + frame.fromB(state->warm_direction));
    centre = geometry::analyticCentre(s.faces, guess - frame.origin, newton);
    tr.warm_point = !centre.start_rejected;
  }
  if (centre.start_rejected) {
    const Vec3 line = frame.centre_a - frame.centre_b;
    const Halfspaces::Chord chord = s.faces.chord(Vec3::Zero(), line);
    if (chord.t_max > chord.t_min) {
      centre = geometry::analyticCentre(s.faces, 0.5 * (chord.t_min + chord.t_max) * line, newton);
      tr.centre_line = !centre.start_rejected;
    } else if (separatedAlong(a, b, a.rotation * -line, touch)) {
      tr.centre_line_apart = true;
      if (state != nullptr) {
        state->warm_direction = -line;
        state->warm_valid = (state->warm_valid & ~kWarmPoint) | kWarmAxis;
      }
      return centre;
    }
  }
  if (centre.start_rejected) {
    const std::optional<Vec3> inside = overlapLp(s, na, touch, state);
    if (!inside) return centre;
    newton.start_margin = 0.0;  // every slack there is at least -s* > touch
    centre = geometry::analyticCentre(s.faces, *inside, newton);
  }
  tr.newton_iterations = centre.iterations;
  tr.newton_decrement = centre.decrement;
  tr.newton_converged = centre.converged;
  return centre;
}

// The length of the overlap's chord along `u` through the point of slacks s.slack, exact from
// the planes: plane i bounds t (a_i . u) <= s_i.
double chordLength(const LpScratch& s, const Vec3& u) {
  double t_min = -std::numeric_limits<double>::infinity();
  double t_max = std::numeric_limits<double>::infinity();
  for (int i = 0; i < s.faces.size(); ++i) {
    const double rate = s.faces.ax()[i] * u.x() + s.faces.ay()[i] * u.y() + s.faces.az()[i] * u.z();
    if (rate > 0.0) t_max = std::min(t_max, s.slack[i] / rate);
    if (rate < 0.0) t_min = std::max(t_min, s.slack[i] / rate);
  }
  return t_max > t_min ? t_max - t_min : 0.0;
}

}  // namespace

Vec3 innerPotentialGradient(const Halfspaces& faces, int begin, int end, double r, const Vec3& x) {
  Vec3 g = Vec3::Zero();
  for (int i = begin; i < end; ++i) {
    const double w = r - faces.slack(i, x);  // a_i . x - d_i + r
    if (w > 0.0) g += (2.0 * w) * faces.normal(i);
  }
  return g;
}

Vec3 innerPotentialNormal(const Halfspaces& faces, int begin, int end, double r, const Vec3& x) {
  std::vector<double> slack(faces.size());
  for (int i = begin; i < end; ++i) slack[i] = faces.slack(i, x);
  return unitOutward(faces, slack.data(), begin, end, r);
}

LpKernel::LpKernel(const KernelParams& params) : rounding_(params.lp_rounding) {
  if (!(rounding_ > 0.0 && rounding_ < 1.0)) {
    throw Error(cat("lp kernel: lp_rounding must lie in (0, 1) (a fraction of the inradius), got ",
                    rounding_));
  }
}

const LpKernel::Trace& LpKernel::lastTrace() {
  return trace();
}

Contact LpKernel::collide(const Body& a, const Body& b, particles::PairState* state) const {
  Trace& tr = trace();
  tr = Trace{};
  Contact out;
  const double size = a.circumradius() + b.circumradius();
  if ((a.centroid() - b.centroid()).squaredNorm() >= size * size) {
    tr.spheres_apart = true;
    if (state != nullptr) state->warm_valid &= ~kWarmPoint;
    return out;
  }
  const double touch = kTouch * size;
  if (state != nullptr && (state->warm_valid & kWarmAxis) != 0 &&
      separatedAlong(a, b, a.rotation * state->warm_direction, touch)) {
    tr.warm_axis = true;  // still apart across the last separating slab's direction
    return out;
  }

  const PairFrame frame(a, b);
  LpScratch& s = lpScratch();
  const int na = static_cast<int>(a.shape->faces().size());
  const int n = na + static_cast<int>(b.shape->faces().size());
  s.faces.resize(n);
  placeFaces(a, b, frame, s.faces);
  const geometry::AnalyticCentreResult centre = contactCentre(a, b, frame, s, na, touch, state);
  if (centre.start_rejected) return out;  // apart
  const Vec3 x = centre.x;

  // Normal from the two inner potential particles: the bisector of their unit normals.
  s.slack.resize(n);
  for (int i = 0; i < n; ++i) s.slack[i] = s.faces.slack(i, x);
  const Vec3 out_a = unitOutward(s.faces, s.slack.data(), 0, na, rounding_ * a.shape->inradius());
  const Vec3 out_b = unitOutward(s.faces, s.slack.data(), na, n, rounding_ * b.shape->inradius());
  Vec3 normal = out_b - out_a;
  out.status = centre.converged ? Status::kOk : Status::kNotConverged;
  if (normal.norm() < kOpposedMin) {
    // The two normals agree (one block inside the other, near a common face) or both vanish:
    // push A away from B's centroid, or out through B's nearest face if the centroids coincide.
    out.status = Status::kDegenerate;
    normal = frame.centre_a - frame.centre_b;
    if (normal.norm() <= touch) {
      const auto nearest = std::min_element(s.slack.begin() + na, s.slack.end());
      normal = s.faces.normal(static_cast<int>(nearest - s.slack.begin()));
    }
  }
  normal.normalize();

  const Vec3 point = frame.origin + x;  // in A's frame
  out.depth = chordLength(s, normal);
  out.touching = out.depth > 0.0;
  out.normal = a.rotation * normal;
  out.point = a.toWorld(point);
  if (state != nullptr) {
    state->warm_point = point;
    state->warm_direction = frame.toB(point);
    state->warm_valid = (state->warm_valid | kWarmPoint) & ~kWarmAxis;
  }
  return out;
}

std::unique_ptr<Kernel> makeLp(const KernelParams& params) {
  return std::make_unique<LpKernel>(params);
}

}  // namespace polydem::contact
