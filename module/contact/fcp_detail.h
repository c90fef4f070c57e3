// Internals shared by the FCP files (fcp_search, fcp_support, fcp_certificate, fcp_point): support
// walks on placed polyhedra, the closest-vertex band, convex ordering and the certificate.
#pragma once

#include <span>
#include <vector>

#include "contact/contact.h"
#include "contact/fcp.h"
#include "geometry/plane_section.h"

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
