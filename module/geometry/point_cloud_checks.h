// Checks on a point cloud before it is handed to the hull builder (internal to the geometry
// module). Every tolerance is relative to the size of the cloud.
#pragma once

#include <span>
#include <string>

#include "polydem/core/types.h"

namespace polydem::geometry {

/// Where a cloud is and how big: the centre and the diagonal of its axis-aligned bounding box.
struct CloudFrame {
  Vec3 centre = Vec3::Zero();
  double size = 0.0;
};

/// Throws GeometryError, naming the offending point indices, for clouds that cannot span a
/// polyhedron: fewer than 4 points, non-finite coordinates, two points closer than
/// RelTol::kPoint * size, or all points within RelTol::kPlane * size of one plane.
CloudFrame checkPointCloud(std::span<const Vec3> points);

/// "3, 7, 12" (at most `max_shown` indices, then ", ... (n in all)").
std::string formatIndices(std::span<const int> indices, std::size_t max_shown = 12);

/// "(x, y, z)" with full precision.
std::string formatPoint(const Vec3& p);

}  // namespace polydem::geometry
