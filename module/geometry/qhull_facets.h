// Thin wrapper around libqhull_r (internal to the geometry module): the convex hull of a point
// cloud as plain facets, with no qhull type leaking out. Qhull runs on its own qhT (reentrant, no
// global state); its messages are captured and never reach stdout or stderr.
#pragma once

#include <span>
#include <vector>

#include "polydem/core/types.h"

namespace polydem::geometry {

struct QhullFacet {
  std::vector<int> points;      // input indices of the facet's vertices, in no particular order
  std::vector<int> neighbours;  // indices into the returned facet list
  Vec3 normal;                  // unit, outward
  double offset = 0.0;          // normal . x = offset on the facet
};

/// The facets qhull finds for `points` (default options: facets coplanar to round-off are merged,
/// so facets may have more than three vertices). Throws GeometryError carrying qhull's message if
/// qhull fails. The caller normalises the cloud (centre and size ~ 1) for best accuracy.
std::vector<QhullFacet> qhullFacets(std::span<const Vec3> points);

}  // namespace polydem::geometry
