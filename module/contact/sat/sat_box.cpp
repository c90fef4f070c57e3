// The nine edge axes of two parallelepipeds (sat_detail.h, boxEdgeAxes): each axis's overlap is
// bounded from products the nine share, and only the axes the bound cannot rule out are tested
// exactly, so that the answer is the full test's (separatingAxisTestReference), bit for bit.
//
// Shared products. The clouds are parallelepipeds with centres c_A, c_B and edges e_k, f_l
// (Cloud); the axis edges of each body are its cloud edges, the same subtraction bit for bit
// (cloudEdgeOf). For the axis U = e_k x f_l (computed as edgeAxes() does) and t = c_A - c_B the
// overlap (1) of sat.h, unnormalised, is min(plus, minus) = h_A + h_B - |U . t| with
// h_A = sum_m |U . e_m| / 2, h_B = sum_m |U . f_m| / 2. In exact arithmetic U . e_k = 0 and, for
// m != k, |U . e_m| = |f_l . (e_m x e_k)| = |f_l . E_n| with E_n = e_{n+1} x e_{n+2} the face
// normals of the cloud (n the third index), so
//     h_A = (|E_{k+1} . f_l| + |E_{k+2} . f_l|) / 2,  h_B = (|F_{l+1} . e_k| + |F_{l+2} . e_k|) / 2
// from the 2 x 9 products E . f and F . e (indices mod 3): one dot product an axis (U . t) where
// the exact test takes a normalisation and eight.
//
// The bound. Let u be the unit roundoff, C = |c_A| + |c_B|, a and b the longest edges of A and B,
// n = |U|, and L = |t| + 3(a + b) / 2 (the overlap is L-Lipschitz in the axis). Standard
// round-off bounds (Higham 2002, sec. 3.1: a dot product of 3 terms within gamma_3 |x||y|, a cross
// product within 3u |x||y|) give, for the estimate d~ = (h_A + h_B - |U . t|) / n computed here
// and the overlap d that Search::test computes from U.normalized() and extent():
//   - the estimate against the exact overlap along U / n: E . f and F . e within 6.1u a^2 b and
//     6.1u a b^2, the rounded U against e_k x f_l within 3u ab, so h_A + h_B within
//     12.6u ab(a + b); U . t within 4.1u n|t|; their difference within u (1.5 ab(a + b) + n|t|);
//     the division and n within 4u L;
//   - the exact test against the same: U.normalized() within 4u of U / n (4u L), its extents
//     within 5.1u C + 12.1u (a + b);
// in all |d~ - d| <= u (20 C + 26 (a + b) + 15 ab(a + b) / n), the evaluation of the bound and of
// d~ -+ bound included. The bound used, 32u (C + (a + b)(1 + ab / n)), covers it with a
// margin. It assumes no underflow or overflow: edges between 1e-50 and C + a + b below 1e50.
//
// Which axes are tested, and why the answer is the same. The full test takes the axes in order
// (faces of A, of B, then e_i x f_j with j fastest): the first whose overlap is <= 0 in either
// sign separates the bodies and ends it; otherwise the minimum stands, where an edge axis
// replaces a face axis only below bar = (face minimum) - tolerance and then any smaller edge axis
// replaces it. So without separation the answer is the face minimum F* unless the smallest edge
// overlap m_E is below bar, and then it is the first edge axis E* with overlap m_E. With lower and
// upper the estimate -+ the bound, this file tests exactly, in order and after the same face axes,
// every edge axis that
//   (a) could separate: lower <= 0 (or not a number), and every edge axis that
//   (b) could be E*: lower <= min over all edge axes of upper, and lower < bar.
// An axis left out by (a) does not separate (d >= lower > 0), so the first separating axis, if
// any, is tested; then kSeparated makes the caller rerun the full test, whose fields on a
// separation hold the minimum over every axis before it. Otherwise: if m_E < bar, E* passes (b)
// (lower <= m_E <= every upper, lower <= m_E < bar), every axis left out has d > m_E (d >= lower >
// some upper >= its axis's d >= m_E, or d >= lower >= bar > m_E), so E* is the first minimum of the
// tested axes and Search picks it as the full test does; if m_E >= bar, no tested edge axis falls
// below bar and F* stands. Search::test computes the chosen axis's normal, depth and features from
// the same operations on the same numbers, and result() the extreme vertices: every field is the
// same.
#include <cmath>
#include <limits>

#include "polydem/contact/sat/sat_detail.h"

namespace polydem::contact::sat_detail {

namespace {

// For each axis edge of the body (axisEdges()), the index k of the cloud edge e_k it is: the edge
// runs from vertex 0 to the neighbour e_k reaches, so v[v1] - v[v0] is e_k's subtraction. false
// if one is not at vertex 0 (fromPoints sorts edges by vertex: the three at vertex 0 come first,
// one of each parallel family, so a parallelepiped's axis edges are those).
bool cloudEdgeOf(const Body& body, int (&k)[3]) {
  const auto& shape = *body.shape;
  const auto& axes = shape.axisEdges();
  if (axes.size() != 3) return false;
  const int* next = shape.vertexNeighbours()[0].data();
  for (int i = 0; i < 3; ++i) {
    const auto& edge = shape.edges()[axes[i]];
    const int to = edge.v1;
    k[i] = edge.v0 != 0 ? -1 : to == next[0] ? 0 : to == next[1] ? 1 : to == next[2] ? 2 : -1;
    if (k[i] < 0) return false;
  }
  return true;
}

}  // namespace

namespace {

// estimateBoxEdges(), handing each existing axis's estimate and bound to `visit(axis, overlap,
// bound)`: inlined into boxEdgeAxes(), which keeps what it needs in registers rather than in
// arrays in memory behind a call (this screen runs for every box pair of a dense pack).
template <class Visit>
[[gnu::always_inline]] inline bool estimate(const Body& a, const Body& b, const Cloud& ca,
                                            const Cloud& cb, int (&ka)[3], int (&kb)[3],
                                            Visit&& visit) {
  if (!cloudEdgeOf(a, ka) || !cloudEdgeOf(b, kb)) return false;
  const Vec3(&e)[3] = ca.e;
  const Vec3(&f)[3] = cb.e;
  const double ee[3] = {e[0].squaredNorm(), e[1].squaredNorm(), e[2].squaredNorm()};
  const double ff[3] = {f[0].squaredNorm(), f[1].squaredNorm(), f[2].squaredNorm()};
  const double C = std::sqrt(ca.centre.squaredNorm()) + std::sqrt(cb.centre.squaredNorm());
  const double la = std::sqrt(std::max(ee[0], std::max(ee[1], ee[2])));
  const double lb = std::sqrt(std::max(ff[0], std::max(ff[1], ff[2])));
  if (!(la > 1e-50 && lb > 1e-50 && C + la + lb < 1e50)) return false;
  // The bound 32u (C + (a + b)(1 + ab / n)) as near + far / n.
  const double slack = 32.0 * (std::numeric_limits<double>::epsilon() / 2);
  const double near = slack * (C + la + lb), far = slack * (la + lb) * la * lb;

  const Vec3 t = ca.centre - cb.centre;
  const Vec3 E[3] = {e[1].cross(e[2]), e[2].cross(e[0]), e[0].cross(e[1])};
  const Vec3 F[3] = {f[1].cross(f[2]), f[2].cross(f[0]), f[0].cross(f[1])};
  double ef[3][3], fe[3][3];  // ef[m][l] = E_m . f_l, fe[m][k] = F_m . e_k
  for (int m = 0; m < 3; ++m) {
    for (int l = 0; l < 3; ++l) ef[m][l] = E[m].dot(f[l]), fe[m][l] = F[m].dot(e[l]);
  }
  // h_A + h_B of the axis e_k x f_l (see above) as half_a[k][l] + half_b[l][k].
  double half_a[3][3], half_b[3][3];
  for (int k = 0; k < 3; ++k) {
    const int k1 = (k + 1) % 3, k2 = (k + 2) % 3;
    for (int l = 0; l < 3; ++l) {
      half_a[k][l] = 0.5 * (std::abs(ef[k1][l]) + std::abs(ef[k2][l]));
      half_b[k][l] = 0.5 * (std::abs(fe[k1][l]) + std::abs(fe[k2][l]));
    }
  }
  for (int ii = 0; ii < 3; ++ii) {
    for (int jj = 0; jj < 3; ++jj) {
      const int k = ka[ii], l = kb[jj];
      const Vec3 u = e[k].cross(f[l]);  // as edgeAxes() computes it
      const double uu = u.squaredNorm();
      if (!edgeAxisExists(uu, ee[k], ff[l])) continue;
      const double n = std::sqrt(uu);
      visit(3 * ii + jj, (half_a[k][l] + half_b[l][k] - std::abs(u.dot(t))) / n, near + far / n);
    }
  }
  return true;
}

}  // namespace

bool estimateBoxEdges(const Body& a, const Body& b, const Cloud& ca, const Cloud& cb,
                      EdgeEstimates& out) {
  out.exists = 0;
  return estimate(a, b, ca, cb, out.k, out.l, [&](int axis, double overlap, double bound) {
    out.exists |= 1u << axis;
    out.overlap[axis] = overlap;
    out.bound[axis] = bound;
  });
}

BoxEdges boxEdgeAxes(const Body& a, const Body& b, const Cloud& ca, const Cloud& cb,
                     Search& search) {
  // With the estimates: the least upper bound, and the axes that (a) or (b) may keep: lower <= 0
  // or lower < bar. Usually none (a face contact), and the exact tests have nothing to do.
  const double bar = search.bar(AxisTest::Axis::kEdges);
  int ka[3], kb[3];
  double lower[9];
  double upper_min = std::numeric_limits<double>::infinity();
  unsigned open = 0;
  const bool applies = estimate(a, b, ca, cb, ka, kb, [&](int axis, double overlap, double bound) {
    const double low = overlap - bound, upper = overlap + bound;
    lower[axis] = low;
    upper_min = upper < upper_min ? upper : upper_min;
    if (!(low > 0.0) || !(low >= bar)) open |= 1u << axis;
  });
  if (!applies) return BoxEdges::kNotApplicable;
  // The exact tests of the axes (a) and (b) above, in order.
  const auto& axis_a = a.shape->axisEdges();
  const auto& axis_b = b.shape->axisEdges();
  for (int axis = 0; open != 0; ++axis, open >>= 1) {
    if (!(open & 1u)) continue;
    const bool may_separate = !(lower[axis] > 0.0);
    const bool may_win = !(lower[axis] > upper_min) && !(lower[axis] >= bar);
    if (!may_separate && !may_win) continue;
    const int ii = axis / 3, jj = axis % 3;
    const Vec3 u = ca.e[ka[ii]].cross(cb.e[kb[jj]]);
    if (!search.test(u.normalized(), AxisTest::Axis::kEdges, axis_a[ii], axis_b[jj])) {
      return BoxEdges::kSeparated;
    }
  }
  return BoxEdges::kDone;
}

}  // namespace polydem::contact::sat_detail
