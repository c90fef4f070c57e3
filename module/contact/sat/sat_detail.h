// Internals of the separating-axis test (sat.h) shared by sat.cpp (every pair, every axis) and
// sat_box.cpp (the edge axes of two parallelepipeds, screened by a cheaper bound): the bodies'
// vertices, their extent along an axis, and the running minimum of (1) over the axes tested.
#pragma once

#include "polydem/contact/sat/sat.h"
#include "polydem/contact/support.h"

namespace polydem::contact::sat_detail {

/// A body's world vertices as structure of arrays, so that the projections onto an axis are
/// one loop of independent multiplies and min/max without index bookkeeping. A parallelepiped
/// (8 vertices, faces parallel in pairs: a cube, a box) is projected in closed form instead and
/// keeps no copy: its centre c and edge vectors e_k (from vertex 0 to its three neighbours) span
/// it as c + sum s_k e_k / 2 with s_k = +-1, so along u its extent is
/// c . u -+ sum |e_k . u| / 2 (Gottschalk et al. 1996), the same numbers as the vertices' up to
/// round-off, with three dot products instead of eight.
struct Cloud {
  static constexpr int kMax = kScanSupportVertices;
  alignas(16) double x[kMax], y[kMax], z[kMax];
  const Vec3* v;
  int n;
  bool box;
  Vec3 centre, e[3];

  explicit Cloud(const Body& body);
};

struct Extent {
  double lo, hi;
};

[[gnu::always_inline]] inline Extent extent(const Cloud& c, const Vec3& u) {
  if (c.box) {
    const double middle = u.dot(c.centre);
    const double half =
        0.5 * (std::abs(u.dot(c.e[0])) + std::abs(u.dot(c.e[1])) + std::abs(u.dot(c.e[2])));
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

/// The running minimum of (1) over the axes tested so far.
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
    if (!have_ || d < bar(axis)) {
      have_ = true;
      best_.normal = along ? u : Vec3(-u);
      best_.depth = d;
      best_.axis = axis;
      best_.feature_a = fa;
      best_.feature_b = fb;
    }
    return true;
  }

  /// The overlap an axis of kind `axis` must fall below to replace the minimum so far: an edge
  /// axis must beat a face axis by more than the tolerance (see sat.h).
  double bar(AxisTest::Axis axis) const {
    const bool face_held = best_.axis != AxisTest::Axis::kEdges;
    return (axis == AxisTest::Axis::kEdges && face_held && have_) ? best_.depth - tolerance_
                                                                  : best_.depth;
  }

  /// The result, with the extreme vertices along the chosen normal.
  const AxisTest& result();

 private:
  const Cloud& a_;
  const Cloud& b_;
  double tolerance_;
  bool have_ = false;
  AxisTest best_;
};

/// Whether the edges ea and eb of the two bodies make an axis u = ea x eb, from the squared norms
/// of the three: parallel edges do not (sat.h).
inline bool edgeAxisExists(double uu, double ee, double ff) {
  const double limit = geometry::ConvexPolyhedron::kParallelAxes;
  return uu > limit * limit * ee * ff;
}

enum class BoxEdges { kDone, kSeparated, kNotApplicable };

/// Estimates of the overlap (1) of the nine edge axes of two parallelepipeds from shared products,
/// each within `bound` of the overlap that Search::test computes (sat_box.cpp), in the full test's
/// order: A's axis edge ii with B's jj at 3 ii + jj, as e[k[ii]] x f[l[jj]] of the clouds' edges.
struct EdgeEstimates {
  double overlap[9], bound[9];
  unsigned exists;  // bit 3 ii + jj: that axis exists (edgeAxisExists)
  int k[3], l[3];
};

/// false where the estimates do not apply (the axis edges are not the clouds' edges, or lengths
/// outside 1e-50..1e50); otherwise fills `out`.
bool estimateBoxEdges(const Body& a, const Body& b, const Cloud& ca, const Cloud& cb,
                      EdgeEstimates& out);

/// The edge axes of two parallelepipeds (sat_box.cpp), after the face axes: each screened by a
/// bound on its overlap from shared products and tested exactly by `search` only where it could
/// separate the bodies or be the minimum, so that `search` ends as if it had tested all nine.
/// kSeparated: an exact test separated the bodies, and `search` does not hold the minimum of the
/// axes before that one (the caller runs the full test); kNotApplicable: the bodies' axis edges
/// are not the edges of their clouds, nothing was tested.
BoxEdges boxEdgeAxes(const Body& a, const Body& b, const Cloud& ca, const Cloud& cb,
                     Search& search);

/// The separating-axis test of two rectangular boxes (both shapes have a box(): sat_obb.cpp), from
/// the products of their rotations; the answer of separatingAxisTestReference() up to round-off
/// (within about 1e-15 of the pair's size and distance from the origin).
AxisTest boxTest(const Body& a, const Body& b, const Vec3* warm, double tolerance);

}  // namespace polydem::contact::sat_detail
