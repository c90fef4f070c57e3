// The first direction of every family of parallel ones (internal to the geometry module): the
// separating axes of a polyhedron's faces and edges (ConvexPolyhedron::axisFaces, axisEdges).
#pragma once

#include <span>
#include <vector>

#include "polydem/core/types.h"

namespace polydem::geometry {

/// Indices of `directions` (unit vectors), in order, keeping each one not parallel up to sign to
/// one kept before it: |d x e| <= sin_angle counts as parallel. The result is that of comparing
/// every direction with every kept one; a grid over the unit sphere finds the few candidates, so
/// a polyhedron of 10^5 faces (all distinct) takes milliseconds instead of minutes.
/// `sin_angle` must be small (below 1e-3).
std::vector<int> distinctDirections(std::span<const Vec3> directions, double sin_angle);

}  // namespace polydem::geometry
