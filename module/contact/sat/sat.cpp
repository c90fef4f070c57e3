#include "polydem/contact/sat/sat.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "polydem/contact/sat/sat_detail.h"
#include "polydem/contact/support.h"
#include "polydem/geometry/box_frame.h"

namespace polydem::contact {

namespace sat_detail {

Cloud::Cloud(const Body& body)
    : v(body.vertices.data()), n(static_cast<int>(body.vertices.size())) {
  box = n == 8 && body.shape->axisFaces().size() == 3;
  if (box) {
    const auto& next = body.shape->vertexNeighbours()[0];  // three: a corner of the box
    e[0] = v[next[0]] - v[0], e[1] = v[next[1]] - v[0], e[2] = v[next[2]] - v[0];
    centre = v[0] + 0.5 * (e[0] + e[1] + e[2]);
    return;  // extent() and lowest() need no copy
  }
  for (int i = 0; i < n; ++i) x[i] = v[i].x(), y[i] = v[i].y(), z[i] = v[i].z();
}

namespace {

/// The first vertex lowest along u (the dot products of extent()'s vertex loop).
int lowest(const Cloud& c, const Vec3& u) {
  int best = 0;
  double value = u.x() * c.v[0].x() + u.y() * c.v[0].y() + u.z() * c.v[0].z();
  for (int i = 1; i < c.n; ++i) {
    const double d = u.x() * c.v[i].x() + u.y() * c.v[i].y() + u.z() * c.v[i].z();
    if (d < value) value = d, best = i;
  }
  return best;
}

}  // namespace

const AxisTest& Search::result() {
  if (!best_.separated) {
    best_.lowest_a = lowest(a_, best_.normal);
    best_.highest_b = lowest(b_, -best_.normal);
  }
  return best_;
}

}  // namespace sat_detail

namespace {

using sat_detail::Cloud;
using sat_detail::edgeAxisExists;
using sat_detail::extent;
using sat_detail::Search;

int projections(const Body& a, const Body& b) {
  const auto& sa = *a.shape;
  const auto& sb = *b.shape;
  const int axes = static_cast<int>(sa.axisFaces().size() + sb.axisFaces().size() +
                                    sa.axisEdges().size() * sb.axisEdges().size());
  return axes * static_cast<int>(a.vertices.size() + b.vertices.size());
}

}  // namespace

bool satApplies(const Body& a, const Body& b) {
  // Two rectangular boxes: 8 vertices each and 3 + 3 + 9 axes, 240 projections.
  static_assert(Cloud::kMax >= 8 && 15 * 16 <= kSatMaxProjections);
  if (a.shape->box() != nullptr && b.shape->box() != nullptr) return true;
  return a.vertices.size() <= Cloud::kMax && b.vertices.size() <= Cloud::kMax &&
         projections(a, b) <= kSatMaxProjections;
}

namespace {

// The warm axis of the last step, if it still separates the bodies: one projection decides.
bool warmSeparates(const Cloud& ca, const Cloud& cb, const Vec3* warm) {
  return warm != nullptr && warm->squaredNorm() > 0.0 &&
         extent(ca, *warm).lo - extent(cb, *warm).hi >= 0.0;
}

AxisTest separatedAlong(const Vec3& axis) {
  AxisTest r;
  r.separated = true;
  r.normal = axis;
  return r;
}

// The face axes of A, then of B, in order; false if one separates the bodies.
bool faceAxes(const Body& a, const Body& b, Search& search) {
  for (int f : a.shape->axisFaces()) {
    if (!search.test(a.faceNormal(f), AxisTest::Axis::kFaceA, f, -1)) return false;
  }
  for (int f : b.shape->axisFaces()) {
    if (!search.test(b.faceNormal(f), AxisTest::Axis::kFaceB, -1, f)) return false;
  }
  return true;
}

// Every edge axis, each tested exactly, in order; false if one separates the bodies.
bool edgeAxes(const Body& a, const Body& b, Search& search) {
  const auto& edges_a = a.shape->edges();
  const auto& edges_b = b.shape->edges();
  for (int i : a.shape->axisEdges()) {
    const Vec3 ea = a.vertices[edges_a[i].v1] - a.vertices[edges_a[i].v0];
    for (int j : b.shape->axisEdges()) {
      const Vec3 eb = b.vertices[edges_b[j].v1] - b.vertices[edges_b[j].v0];
      const Vec3 u = ea.cross(eb);
      // Parallel edges: no axis of their own (sat.h).
      if (!edgeAxisExists(u.squaredNorm(), ea.squaredNorm(), eb.squaredNorm())) continue;
      if (!search.test(u.normalized(), AxisTest::Axis::kEdges, i, j)) return false;
    }
  }
  return true;
}

}  // namespace

AxisTest separatingAxisTestReference(const Body& a, const Body& b, const Vec3* warm,
                                     double tolerance) {
  const Cloud ca(a), cb(b);
  if (warmSeparates(ca, cb, warm)) return separatedAlong(*warm);
  Search search(ca, cb, tolerance);
  if (!faceAxes(a, b, search)) return search.result();
  edgeAxes(a, b, search);
  return search.result();
}

AxisTest separatingAxisTest(const Body& a, const Body& b, const Vec3* warm, double tolerance) {
  if (a.shape->box() != nullptr && b.shape->box() != nullptr) {
    return sat_detail::boxTest(a, b, warm, tolerance);
  }
  const Cloud ca(a), cb(b);
  if (warmSeparates(ca, cb, warm)) return separatedAlong(*warm);
  Search search(ca, cb, tolerance);
  if (!faceAxes(a, b, search)) return search.result();
  if (ca.box && cb.box) {
    switch (sat_detail::boxEdgeAxes(a, b, ca, cb, search)) {
      case sat_detail::BoxEdges::kDone:
        return search.result();
      case sat_detail::BoxEdges::kSeparated:  // rare: a pair apart that no face axis separates
        return separatingAxisTestReference(a, b, warm, tolerance);
      case sat_detail::BoxEdges::kNotApplicable:
        break;
    }
  }
  edgeAxes(a, b, search);
  return search.result();
}

namespace {

// For a rectangular box (BoxFrame): the edge at vertex v along box axis k, as its two ends (v
// first), from the corner table alone: v's corner bits with bit k flipped. For an axis edge `like`
// along k it is the edge edgeAt() below picks: at a corner of a box the three edges lie along the
// three axes (orthogonal within BoxFrame::kMaxSkew), so the parallel edge's cosine is 1 and the
// others' that skew plus the round-off of the world vertices, u (|x| + size) / edge: never a tie.
std::pair<Vec3, Vec3> boxEdgeAt(const Body& body, const geometry::BoxFrame& box, int v, int k) {
  int bits = 0;
  while (box.corner[bits] != v) ++bits;
  const int other = box.corner[bits ^ (1 << k)];
  return {body.vertices[v], body.vertices[other]};
}

// The edge at vertex v of `body` most nearly parallel to the edge `like`, as its two ends (v
// first).
std::pair<Vec3, Vec3> edgeAt(const Body& body, int v, int like) {
  const auto& shape = *body.shape;
  if (const auto* box = shape.box()) {
    const auto& axis_edges = shape.axisEdges();
    for (int i = 0; i < 3; ++i) {
      if (axis_edges[i] == like) return boxEdgeAt(body, *box, v, box->edge_axis[i]);
    }
  }
  const auto& ref = shape.edges()[like];
  const Vec3 d = (body.vertices[ref.v1] - body.vertices[ref.v0]).normalized();
  int best = -1;
  double best_cos = -1.0;
  for (int e : shape.vertexEdges()[v]) {
    const auto& edge = shape.edges()[e];
    const Vec3 f = body.vertices[edge.v1] - body.vertices[edge.v0];
    const double c = std::abs(d.dot(f)) / f.norm();
    if (c > best_cos) best = e, best_cos = c;
  }
  const auto& edge = shape.edges()[best];
  const int other = edge.v0 == v ? edge.v1 : edge.v0;
  return {body.vertices[v], body.vertices[other]};
}

}  // namespace

Vec3 crossingPoint(const Body& a, const Body& b, const AxisTest& t) {
  // Closest points of the segments p + s d and q + r e, s and r clamped to [0, 1].
  const auto [p, p1] = edgeAt(a, t.lowest_a, t.feature_a);
  const auto [q, q1] = edgeAt(b, t.highest_b, t.feature_b);
  const Vec3 d = p1 - p, e = q1 - q, w = p - q;
  const double dd = d.dot(d), de = d.dot(e), ee = e.dot(e), dw = d.dot(w), ew = e.dot(w);
  const double denominator = dd * ee - de * de;
  // Edges parallel to round-off (the supporting features are not the axis's two edges: a tie
  // with a face axis): the middle of the two deepest vertices.
  const double limit = geometry::ConvexPolyhedron::kParallelAxes;
  if (!(denominator > limit * limit * dd * ee)) return 0.5 * (p + q);
  const double s = std::clamp((de * ew - ee * dw) / denominator, 0.0, 1.0);
  const double r = std::clamp((dd * ew - de * dw) / denominator, 0.0, 1.0);
  return 0.5 * (p + s * d + q + r * e);
}

}  // namespace polydem::contact
