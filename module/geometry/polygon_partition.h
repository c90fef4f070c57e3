// A simple polygon (convex or not) as a few convex polygons: ear clipping into triangles, then
// Hertel and Mehlhorn's merge (drop every diagonal whose removal leaves both corners convex),
// which gives at most four times the fewest convex pieces. Used for slope profiles, whose toe and
// benches make the profile non-convex.
#pragma once

#include <vector>

#include "polydem/core/types.h"

namespace polydem::geometry {

/// Convex pieces of the simple polygon `polygon` (corners in order, either orientation), each
/// counter-clockwise, covering it without overlap. Corners on a straight line between their
/// neighbours are dropped first. Throws GeometryError for fewer than three corners, repeated
/// corners, zero area or crossing edges; tolerances are relative to the polygon's size.
std::vector<std::vector<Vec2>> convexPartition(const std::vector<Vec2>& polygon);

/// Twice the signed area (> 0: counter-clockwise).
double twiceSignedArea(const std::vector<Vec2>& polygon);

}  // namespace polydem::geometry
