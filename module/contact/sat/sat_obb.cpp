// The separating-axis test of two rectangular boxes (sat_detail.h, boxTest), the classical way
// (Gottschalk et al. 1996, "OBBTree", sec. 4; Ericson 2005, Real-Time Collision Detection,
// sec. 4.4.1): all 15 axes from the nine products R_kl = a_k . b_l of the boxes' world axes and
// the centre offset t = c_B - c_A in A's frame, instead of projecting both bodies on every axis.
//
// Along a unit axis u the overlap (1) of sat.h is r - |s| with r = sum_k h_k |u . a_k| +
// sum_l g_l |u . b_l| (h, g the half sides of A and B) and s = u . t; plus = r + s, minus = r - s.
//   - face axis a_k: r = h_k + sum_l g_l |R_kl|, s = (A^T t)_k; face axis b_l likewise with
//     (B^T t)_l;
//   - edge axis L = a_k x b_l (unnormalised; k1, k2 the other two indices of A, l1, l2 of B):
//     in A's frame L = (R_k1l on k2, -R_k2l on k1) up to A's handedness, so
//     r = h_k1 |R_k2l| + h_k2 |R_k1l| + g_l1 |R_kl2| + g_l2 |R_kl1|,
//     |s| = |(A^T t)_k2 R_k1l - (A^T t)_k1 R_k2l|, |L|^2 = R_k1l^2 + R_k2l^2,
//   and the overlap along L / |L| is D / |L| with D = r - |s|.
// The face axes are evaluated from these products in the full test's order (faces of A, of B), with
// the same normal (the rotated face normal), minimum and face-over-edge tolerance rule (Search).
//
// Edge axes: D / |L| is not used as the answer, because for nearly parallel edges (|L| ~ the
// relative turn, 1e-9 on a settled pack) its round-off, about u (|t| + sides) / |L|, would make a
// face contact an edge contact or two touching boxes apart. Instead D screens the axes: with
// `slack` a bound on the round-off of D (below), an axis is normalised and projected on both
// boxes (r and s along u = L / |L| from the world axes, no division by |L| in the overlap) only
// where it could separate (D - slack <= 0) or be the new minimum ((D - slack) / |L| below the
// bar of Search, compared squared, without a root). So the answer on an edge axis has the round-off
// of one projection, as the full test's, and a face contact stays one.
//
// The round-off of D: the world axes are the rotations applied to unit vectors (a few u each,
// plus the box's own skew), so R_kl and (A^T t) are within eta = 64u + 8 skew of their exact
// values relative to 1 and |t|, and D within eta (sum h + sum g + 2 |t|_1); the exact projection
// differs from the exact D / |L| by the same over |L| (its axis direction is within eta / |L|).
//
// The warm axis w (sat.h) ends the test where it separates the boxes, W = (c_A - c_B) . w -
// r_A(w) - r_B(w) >= 0 as computed. The test tries it only where it ends apart or with a depth
// d <= tolerance + 1e-6 S (S = sum h + sum g + 2 |A^T t|_1, the scale of the bound on D), which
// gives its old answer everywhere: -W is the overlap (1) along w, at least the penetration depth,
// and d exceeds the depth by at most the tolerance (an edge axis passed over for a face axis),
// the round-off of the axes and extents (eta S, eta <= 1e-13) and what an axis of two edges
// parallel within kParallelAxes (1e-10 rad; they give no axis, sat.h) could hold below its
// neighbours on the Gauss map (about 2 pi 1e-10 times the edge: below 1e-9 S); W has round-off
// below 16u S. So where d is larger, W < 0 by 1e3 times those bounds. On a dense pack (depths of
// 1e-3 of the size) the warm test is then left out of nearly every call; ctest contact_sat
// (WarmAxisOnlyWhereNearlyApart) checks the answer against the warm test done first.
#include <cmath>
#include <limits>

#include "polydem/contact/sat/sat_detail.h"
#include "polydem/geometry/box_frame.h"

namespace polydem::contact::sat_detail {

namespace {

using geometry::BoxFrame;
constexpr double kUnitRoundoff = std::numeric_limits<double>::epsilon() / 2;
// Overlaps below kWarmMargin (sum h + sum g + 2 |A^T t|_1) beyond the tolerance take the warm
// axis's test (see the top of the file).
constexpr double kWarmMargin = 1e-6;

// A box in world coordinates: its centre and unit axes. An axis a_k is the normal of face
// axisFaces()[k] (BoxFrame), so its world direction is Body::faceNormal of that face: in the
// contact phase a copy of the rotated normal that the particle storage computed once per step with
// the same product, instead of three 3 x 3 products per body and pair.
struct WorldBox {
  const BoxFrame& frame;
  Vec3 centre;
  Vec3 axis[3];

  WorldBox(const Body& body, const BoxFrame& f) : frame(f) {
    centre = body.position + body.rotation * f.centre;
    const auto& faces = body.shape->axisFaces();
    for (int k = 0; k < 3; ++k) axis[k] = body.faceNormal(faces[k]);
  }

  // Half the box's extent along the unit axis u.
  double radius(const Vec3& u) const {
    return frame.half[0] * std::abs(u.dot(axis[0])) + frame.half[1] * std::abs(u.dot(axis[1])) +
           frame.half[2] * std::abs(u.dot(axis[2]));
  }

  // The corner lowest along u (on a tie, either: they are lowest within round-off).
  int lowest(const Vec3& u) const {
    int bits = 0;
    for (int k = 0; k < 3; ++k) bits |= u.dot(axis[k]) < 0.0 ? 1 << k : 0;
    return frame.corner[bits];
  }
};

// The running minimum over the axes, as Search keeps it; the normal is formed only when the
// pair is found apart or at the end.
class Minimum {
 public:
  explicit Minimum(double tolerance) : tolerance_(tolerance) {}

  double bar(AxisTest::Axis axis) const {
    const bool face_held = best_.axis != AxisTest::Axis::kEdges;
    return (axis == AxisTest::Axis::kEdges && face_held && have_) ? best_.depth - tolerance_
                                                                  : best_.depth;
  }

  // The axis u (unit) with radii sum r and centre offset s = u . t; false if it separates the
  // bodies (the result then holds the separating direction).
  bool offer(double r, double s, const Vec3& u, AxisTest::Axis axis, int fa, int fb) {
    const double d = r - std::abs(s);
    if (!(d > 0.0)) {
      best_.separated = true;
      best_.normal = r + s > 0.0 ? Vec3(-u) : u;
      return false;
    }
    if (!have_ || d < bar(axis)) {
      have_ = true;
      best_.normal = s <= 0.0 ? u : Vec3(-u);  // plus <= minus: A moves along +u
      best_.depth = d;
      best_.axis = axis;
      best_.feature_a = fa;
      best_.feature_b = fb;
    }
    return true;
  }

  AxisTest& result() { return best_; }

 private:
  double tolerance_;
  bool have_ = false;
  AxisTest best_;
};

// The answer where the warm axis w (may be null) is tried: w if it separates the boxes, else
// `found`. Out of line: it is rare on a dense pack (see the top), and inlined it made the
// compiler keep more of boxTest's products on the stack.
[[gnu::noinline]] AxisTest warmOr(const WorldBox& A, const WorldBox& B, const Vec3* warm,
                                  const AxisTest& found) {
  if (warm != nullptr && warm->squaredNorm() > 0.0 &&
      (A.centre - B.centre).dot(*warm) - A.radius(*warm) - B.radius(*warm) >= 0.0) {
    AxisTest r;
    r.separated = true;
    r.normal = *warm;
    return r;
  }
  return found;
}

}  // namespace

AxisTest boxTest(const Body& a, const Body& b, const Vec3* warm, double tolerance) {
  const WorldBox A(a, *a.shape->box()), B(b, *b.shape->box());
  const Vec3& h = A.frame.half;
  const Vec3& g = B.frame.half;
  const Vec3 t = B.centre - A.centre;
  double R[3][3], abs_r[3][3];
  for (int k = 0; k < 3; ++k) {
    for (int l = 0; l < 3; ++l) R[k][l] = A.axis[k].dot(B.axis[l]), abs_r[k][l] = std::abs(R[k][l]);
  }
  const double ta[3] = {t.dot(A.axis[0]), t.dot(A.axis[1]), t.dot(A.axis[2])};
  Minimum best(tolerance);
  const auto& faces_a = a.shape->axisFaces();
  const auto& faces_b = b.shape->axisFaces();
  for (int k = 0; k < 3; ++k) {
    const double r = h[k] + g[0] * abs_r[k][0] + g[1] * abs_r[k][1] + g[2] * abs_r[k][2];
    if (!best.offer(r, ta[k], A.axis[k], AxisTest::Axis::kFaceA, faces_a[k], -1)) {
      return warmOr(A, B, warm, best.result());
    }
  }
  for (int l = 0; l < 3; ++l) {
    const double r = g[l] + h[0] * abs_r[0][l] + h[1] * abs_r[1][l] + h[2] * abs_r[2][l];
    if (!best.offer(r, t.dot(B.axis[l]), B.axis[l], AxisTest::Axis::kFaceB, -1, faces_b[l])) {
      return warmOr(A, B, warm, best.result());
    }
  }
  // The edge axes in the full test's order, screened by D (see the top of the file).
  const double eta = 64.0 * kUnitRoundoff + 8.0 * (A.frame.skew + B.frame.skew);
  const double scale =
      h.sum() + g.sum() + 2.0 * (std::abs(ta[0]) + std::abs(ta[1]) + std::abs(ta[2]));
  const double slack = eta * scale;
  const double limit = geometry::ConvexPolyhedron::kParallelAxes;
  const auto& edges_a = a.shape->axisEdges();
  const auto& edges_b = b.shape->axisEdges();
  // Every axis a_k x b_l's |L|^2 and its overlap's lower bound D - slack, with constant indices
  // (unrolled, in registers); then the full test's order picks the candidates.
  double LL[3][3], lower[3][3];
  for (int k = 0; k < 3; ++k) {
    const int k1 = k == 2 ? 0 : k + 1, k2 = k == 0 ? 2 : k - 1;
    for (int l = 0; l < 3; ++l) {
      const int l1 = l == 2 ? 0 : l + 1, l2 = l == 0 ? 2 : l - 1;
      LL[k][l] = R[k1][l] * R[k1][l] + R[k2][l] * R[k2][l];
      const double r =
          h[k1] * abs_r[k2][l] + h[k2] * abs_r[k1][l] + g[l1] * abs_r[k][l2] + g[l2] * abs_r[k][l1];
      lower[k][l] = r - std::abs(ta[k2] * R[k1][l] - ta[k1] * R[k2][l]) - slack;
    }
  }
  for (int i = 0; i < 3; ++i) {
    const int k = A.frame.edge_axis[i];
    for (int j = 0; j < 3; ++j) {
      const int l = B.frame.edge_axis[j];
      if (!(LL[k][l] > limit * limit)) continue;  // parallel edges: no axis (sat.h)
      const double low = lower[k][l], bar = best.bar(AxisTest::Axis::kEdges);
      if (low > 0.0 && !(bar > 0.0 && low * low < bar * bar * LL[k][l])) continue;
      const double sign = A.frame.edge_sign[i] * B.frame.edge_sign[j];
      const Vec3 u = (sign * A.axis[k].cross(B.axis[l])).normalized();  // along e_a x e_b
      if (!best.offer(A.radius(u) + B.radius(u), u.dot(t), u, AxisTest::Axis::kEdges, edges_a[i],
                      edges_b[j])) {
        return warmOr(A, B, warm, best.result());
      }
    }
  }
  AxisTest& result = best.result();
  result.lowest_a = A.lowest(result.normal);
  result.highest_b = B.lowest(-result.normal);
  if (!(result.depth > tolerance + kWarmMargin * scale)) return warmOr(A, B, warm, result);
  return result;
}

}  // namespace polydem::contact::sat_detail
