// Internals shared by the FCP files (fcp_search, fcp_support, fcp_certificate, fcp_point): support
// walks on placed polyhedra, the closest-vertex band, convex ordering and the certificate.
#pragma once

#include <span>
#include <vector>

#include "polydem/contact/contact.h"
#include "polydem/contact/fcp/fcp.h"
#include "polydem/geometry/plane_section.h"

namespace polydem::contact::fcp_detail {

/// Length scale of a pair for relative tolerances.
inline double lengthScale(const Body& a, const Body& b) {
  return a.circumradius() + b.circumradius();
}

struct Extreme {
  int index = 0;
  double value = 0.0;
};

/// The vertex of `body` maximising d . x, by steepest ascent over the vertex graph from `hint`
/// (on a convex polyhedron a vertex no neighbour improves on is a global maximiser).
Extreme climbMax(const Body& body, const Vec3& d, int hint);

/// The same without a hint: a scan for small polyhedra, a climb from vertex 0 for large ones.
Extreme supportMax(const Body& body, const Vec3& d);

/// Appends to `out` (cleared first) the vertices x of `body` with d . x >= threshold, found by a
/// walk from `seed`, which must satisfy it: on a convex polyhedron the vertices above any level
/// form a connected subgraph containing the maximiser. Returns the maximiser and d . x there.
Extreme collectBand(const Body& body, const Vec3& d, int seed, double threshold,
                    std::vector<int>& out);

/// An edge of a placed body prepared for the Minkowski-face test. A direction c lies in the cone
/// of outward normals of the edge, {s u0 + t u1 : s, t >= 0}, iff c.p >= 0 and c.q >= 0 with
/// w = u0 x u1, p = u1 x w, q = w x u0 (c = s u0 + t u1 gives c x u1 = s w, u0 x c = t w).
struct EdgeCone {
  Vec3 dir, point, p, q;
  double length = 0.0;  // |dir|
  double scale = 0.0;   // |w|, the sine of the angle between the faces' normals
  int v0 = 0;
};

/// The cone of edge e of `body`, whose faces have the world normals u0 (edge.f0) and u1 (f1).
EdgeCone edgeCone(const Body& body, int e, const Vec3& u0, const Vec3& u1);
EdgeCone edgeCone(const Body& body, int e);

/// +1 if c lies in the edge's normal cone, -1 if -c does, 0 if neither; c_norm2 = |c|^2.
int coneSide(const EdgeCone& e, const Vec3& c, double c_norm2);

/// Largest x . v over the unit vectors v of the arc from unit u0 to unit u1 (an edge's normal
/// cone): |projection of x on their plane| when it lies in the cone, else the larger end.
double maxOverArc(const Vec3& u0, const Vec3& u1, const Vec3& x);

/// World normals of all faces of `body`.
void worldNormals(const Body& body, std::vector<Vec3>& out);

/// The edge joining adjacent vertices v0 and v1 of the body's shape, or -1.
int edgeBetween(const Body& body, int v0, int v1);

/// Counter-clockwise (about n) convex hull of the points projected on the plane: writes indices
/// into `points` to `order` and returns their count (collinear and coincident points dropped).
int convexOrder(std::span<const Vec3> points, const geometry::PlaneFrame& frame,
                std::vector<int>& order);

/// The closest-vertex sets of a plane and the penetration they carry.
struct PlaneFeatures {
  std::span<const int> band_a, band_b;  // vertex indices of A near level_a, of B near level_b
  Vec3 normal;
  double depth = 0.0;  // level_b - level_a > 0
};

/// Certificate that no candidate normal gives a smaller penetration than `f.depth` - slack:
/// a lower bound on the minimum penetration of A and B from convex pieces of each (a closest
/// vertex and the other body; pieces of both bodies spanned by their contact features). True when
/// the bound reaches the depth. Cost: tens to a few hundred dot products for vertex-face,
/// edge-edge, edge-face and face-face contacts.
bool certifyMinimumPenetration(const Body& a, const Body& b, const PlaneFeatures& f, double slack);

}  // namespace polydem::contact::fcp_detail
