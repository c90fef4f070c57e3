// The Delaunay triangulation of points in a plane (x, y), for a surface z(x, y) given by its
// heights at scattered points: the phreatic surface of [water] through more than three points.
// Deterministic: the points are swept in the order of (x, y), each new one joined to the edges of
// the hull it sees, and the triangulation is then made Delaunay by edge flips (Lawson), flipping
// only where a point lies inside a circumcircle by more than round-off; points on one circle
// (a regular grid) keep the sweep's diagonal. The same points give the same triangles.
#pragma once

#include <array>
#include <span>
#include <string>
#include <vector>

namespace polydem::geometry {

using PlanPoint = std::array<double, 2>;
using PlanTriangle = std::array<int, 3>;  // indices of points, counter-clockwise

struct PlanTriangulation {
  std::vector<PlanTriangle> triangles;
  /// What is wrong with the points, empty when they were triangulated: two points at one place in
  /// plan, or all of them on one line.
  std::string error;
};

/// The Delaunay triangulation of `points` (at least three, not all on one line, no two at one
/// place; a relative tolerance of 1e-9 of their extent).
PlanTriangulation delaunayTriangulation(std::span<const PlanPoint> points);

/// Twice the signed area of (a, b, c): > 0 when counter-clockwise.
inline double orient(const PlanPoint& a, const PlanPoint& b, const PlanPoint& c) {
  return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
}

}  // namespace polydem::geometry
