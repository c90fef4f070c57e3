// ConvexPolyhedron::split: the two parts of a convex polyhedron on either side of a plane, as
// vertex lists (each part is the convex hull of its list). Used to cut rock masses by joints.
#include <algorithm>

#include "polydem/core/tolerance.h"
#include "polydem/geometry/polyhedron_split.h"

namespace polydem::geometry {

namespace {

// A part no deeper than this is no part: the joint only grazes the polyhedron.
double thinPart(const ConvexPolyhedron& poly) {
  return 1e-9 * poly.lengthScale();
}

}  // namespace

int splitSide(const ConvexPolyhedron& poly, const Plane& plane) {
  const double thin = thinPart(poly);
  double lowest = 0.0, highest = 0.0;
  for (const Vec3& v : poly.vertices()) {
    const double s = plane.signedDistance(v);
    lowest = std::min(lowest, s);
    highest = std::max(highest, s);
  }
  if (-lowest <= thin) return 1;
  if (highest <= thin) return -1;
  return 0;
}

ConvexPolyhedron::Split ConvexPolyhedron::split(const Plane& plane) const {
  const double scale = lengthScale();
  const double thin = thinPart(*this);  // as splitSide() decides
  // Vertices this close to the plane are on it: they go to both parts and edges ending there are
  // not cut, so no intersection point lands next to a vertex (that would be a near-duplicate).
  const double on_plane = absTol(scale, RelTol::kPlane);

  std::vector<double> s(vertices_.size());
  double lowest = 0.0, highest = 0.0;
  for (std::size_t i = 0; i < vertices_.size(); ++i) {
    s[i] = plane.signedDistance(vertices_[i]);
    lowest = std::min(lowest, s[i]);
    highest = std::max(highest, s[i]);
  }
  Split out;
  if (-lowest <= thin) {
    out.above = vertices_;
    return out;
  }
  if (highest <= thin) {
    out.below = vertices_;
    return out;
  }
  for (std::size_t i = 0; i < vertices_.size(); ++i) {
    if (s[i] <= on_plane) out.below.push_back(vertices_[i]);
    if (s[i] >= -on_plane) out.above.push_back(vertices_[i]);
  }
  // Edges crossing the plane, in edge order (v0 < v1) so both sides of a joint get the same bits.
  for (const Edge& edge : edges_) {
    const double s0 = s[edge.v0], s1 = s[edge.v1];
    if ((s0 < -on_plane && s1 > on_plane) || (s0 > on_plane && s1 < -on_plane)) {
      const Vec3& a = vertices_[edge.v0];
      const Vec3& b = vertices_[edge.v1];
      const Vec3 x = a + (s0 / (s0 - s1)) * (b - a);
      out.below.push_back(x);
      out.above.push_back(x);
    }
  }
  return out;
}

}  // namespace polydem::geometry
