#include "polydem/contact/sat.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "polydem/contact/support.h"

namespace polydem::contact {

namespace {

/// A body's world vertices as structure of arrays, so that the projections onto an axis are
/// one loop of independent multiplies and min/max without index bookkeeping (the vertices
/// extreme on the chosen axis are found once at the end). A parallelepiped (8 vertices, faces
/// parallel in pairs: a cube, a box) is projected in closed form instead: its centre c and edge
/// vectors e_k span it as c + sum s_k e_k / 2 with s_k = +-1, so along u its extent is
/// c . u -+ sum |e_k . u| / 2 (Gottschalk et al. 1996), the same numbers as the vertices' up to
/// round-off, with three dot products instead of eight.
struct Cloud {
  static constexpr int kMax = kScanSupportVertices;
  alignas(16) double x[kMax], y[kMax], z[kMax];
  int n;
  bool box;
  Vec3 centre, e0, e1, e2;

  explicit Cloud(const Body& body) : n(static_cast<int>(body.vertices.size())) {
    const auto& v = body.vertices;
    box = n == 8 && body.shape->axisFaces().size() == 3;
    if (box) {
      const auto& next = body.shape->vertexNeighbours()[0];  // three: a corner of the box
      e0 = v[next[0]] - v[0], e1 = v[next[1]] - v[0], e2 = v[next[2]] - v[0];
      centre = v[0] + 0.5 * (e0 + e1 + e2);
    }
    for (int i = 0; i < n; ++i) x[i] = v[i].x(), y[i] = v[i].y(), z[i] = v[i].z();
  }
};

struct Extent {
  double lo, hi;
};

[[gnu::always_inline]] inline Extent extent(const Cloud& c, const Vec3& u) {
  if (c.box) {
    const double middle = u.dot(c.centre);
    const double half =
        0.5 * (std::abs(u.dot(c.e0)) + std::abs(u.dot(c.e1)) + std::abs(u.dot(c.e2)));
    return {middle - half, middle + half};
  }
  const double ux = u.x(), uy = u.y(), uz = u.z();
  double lo = ux * c.x[0] + uy * c.y[0] + uz * c.z[0], hi = lo;
  for (int i = 1; i < c.n; ++i) {
    const double d = ux * c.x[i] + uy * c.y[i] + uz * c.z[i];
    lo = d < lo ? d : lo;
    hi = d > hi ? d : hi;
  }
  return {lo, hi};
}

/// The first vertex lowest along u (the dot products of extent()'s vertex loop).
int lowest(const Cloud& c, const Vec3& u) {
  int best = 0;
  double value = u.x() * c.x[0] + u.y() * c.y[0] + u.z() * c.z[0];
  for (int i = 1; i < c.n; ++i) {
    const double d = u.x() * c.x[i] + u.y() * c.y[i] + u.z() * c.z[i];
    if (d < value) value = d, best = i;
  }
  return best;
}

/// The running minimum of (1) over the axes seen so far.
class Search {
 public:
  Search(const Cloud& a, const Cloud& b, double tolerance) : a_(a), b_(b), tolerance_(tolerance) {}

  /// Tests the unit axis u in both signs; false if it separates the bodies (the result then
  /// holds the separating direction).
  bool test(const Vec3& u, AxisTest::Axis axis, int fa, int fb) {
    const Extent ea = extent(a_, u), eb = extent(b_, u);
    const double plus = eb.hi - ea.lo;   // A moves along +u
    const double minus = ea.hi - eb.lo;  // A moves along -u
    if (!(plus > 0.0) || !(minus > 0.0)) {
      best_.separated = true;
      best_.normal = plus > 0.0 ? Vec3(-u) : u;
      return false;
    }
    const bool along = plus <= minus;
    const double d = along ? plus : minus;
    // An edge axis must beat a face axis by more than the tolerance (see sat.h).
    const bool face_held = best_.axis != AxisTest::Axis::kEdges;
    const double bar = (axis == AxisTest::Axis::kEdges && face_held && have_)
                           ? best_.depth - tolerance_
                           : best_.depth;
    if (!have_ || d < bar) {
      have_ = true;
      best_.normal = along ? u : Vec3(-u);
      best_.depth = d;
      best_.axis = axis;
      best_.feature_a = fa;
      best_.feature_b = fb;
    }
    return true;
  }

  /// The result, with the extreme vertices along the chosen normal.
  const AxisTest& result() {
    if (!best_.separated) {
      best_.lowest_a = lowest(a_, best_.normal);
      best_.highest_b = lowest(b_, -best_.normal);
    }
    return best_;
  }

 private:
  const Cloud& a_;
  const Cloud& b_;
  double tolerance_;
  bool have_ = false;
  AxisTest best_;
};

int projections(const Body& a, const Body& b) {
  const auto& sa = *a.shape;
  const auto& sb = *b.shape;
  const int axes = static_cast<int>(sa.axisFaces().size() + sb.axisFaces().size() +
                                    sa.axisEdges().size() * sb.axisEdges().size());
  return axes * static_cast<int>(a.vertices.size() + b.vertices.size());
}

}  // namespace

bool satApplies(const Body& a, const Body& b) {
  return a.vertices.size() <= Cloud::kMax && b.vertices.size() <= Cloud::kMax &&
         projections(a, b) <= kSatMaxProjections;
}

AxisTest separatingAxisTest(const Body& a, const Body& b, const Vec3* warm, double tolerance) {
  const Cloud ca(a), cb(b);
  if (warm != nullptr && warm->squaredNorm() > 0.0) {
    // A separating axis of the last step usually still separates: one projection decides.
    const double gap = extent(ca, *warm).lo - extent(cb, *warm).hi;
    if (gap >= 0.0) {
      AxisTest r;
      r.separated = true;
      r.normal = *warm;
      return r;
    }
  }
  Search search(ca, cb, tolerance);
  for (int f : a.shape->axisFaces()) {
    if (!search.test(a.faceNormal(f), AxisTest::Axis::kFaceA, f, -1)) return search.result();
  }
  for (int f : b.shape->axisFaces()) {
    if (!search.test(b.faceNormal(f), AxisTest::Axis::kFaceB, -1, f)) return search.result();
  }
  const auto& edges_a = a.shape->edges();
  const auto& edges_b = b.shape->edges();
  for (int i : a.shape->axisEdges()) {
    const Vec3 ea = a.vertices[edges_a[i].v1] - a.vertices[edges_a[i].v0];
    for (int j : b.shape->axisEdges()) {
      const Vec3 eb = b.vertices[edges_b[j].v1] - b.vertices[edges_b[j].v0];
      const Vec3 u = ea.cross(eb);
      // Parallel edges: no axis of their own (sat.h).
      const double limit = geometry::ConvexPolyhedron::kParallelAxes;
      if (!(u.squaredNorm() > limit * limit * ea.squaredNorm() * eb.squaredNorm())) continue;
      if (!search.test(u.normalized(), AxisTest::Axis::kEdges, i, j)) return search.result();
    }
  }
  return search.result();
}

namespace {

// The edge at vertex v of `body` most nearly parallel to the edge `like`, as its two ends (v
// first).
std::pair<Vec3, Vec3> edgeAt(const Body& body, int v, int like) {
  const auto& shape = *body.shape;
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
