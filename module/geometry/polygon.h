// Convex polygons in a plane (2D coordinates of a PlaneFrame, plane_section.h): ordering,
// point-in-polygon, clipping and intersection, area and area centroid. The pieces of the
// Intersection Polygon Method of Keissar section 2.3 that do not depend on the polyhedra.
//
// Polygons are vertex lists, counter-clockwise. Functions write into caller-owned vectors, which
// keep their capacity between calls, so a hot loop allocates nothing once warm.
#pragma once

#include <span>
#include <vector>

#include "polydem/core/types.h"

namespace polydem::geometry {

/// z-component of the cross product: twice the signed area of the triangle (0, a, b).
inline double cross2(const Vec2& a, const Vec2& b) {
  return a.x() * b.y() - a.y() * b.x();
}

/// Twice the signed area of the triangle (a, b, c); > 0 when it turns counter-clockwise.
inline double orient2(const Vec2& a, const Vec2& b, const Vec2& c) {
  return cross2(b - a, c - a);
}

/// The half-plane {y : normal . y <= offset}.
struct HalfPlane {
  Vec2 normal = Vec2::UnitX();
  double offset = 0.0;
  double value(const Vec2& y) const { return normal.dot(y) - offset; }  // <= 0 inside
};

/// Convex hull of `points`, counter-clockwise from the lowest (x, then y) point, without repeated
/// or collinear points (Andrew's monotone chain). `points` is sorted in place. Fewer than three
/// distinct points give a hull of fewer than three vertices.
void convexHull(std::vector<Vec2>& points, std::vector<Vec2>& hull);

/// Whether p lies in the convex counter-clockwise polygon or within `tolerance` (a length) of it:
/// on the inner side of every edge (Keissar eqs. 2.8-2.9).
bool containsPoint(std::span<const Vec2> polygon, const Vec2& p, double tolerance = 0.0);

/// Sutherland-Hodgman step: writes the part of `polygon` (any simple polygon, in order) inside
/// the half-plane to `out` and returns the number of corners written. `out` needs room for
/// polygon.size() + 1 corners and must not overlap `polygon`.
std::size_t clipByHalfPlane(std::span<const Vec2> polygon, const HalfPlane& half_plane, Vec2* out);

/// The half-plane to the left of the directed edge a -> b (the inside of a counter-clockwise
/// polygon). The edge must have non-zero length.
HalfPlane leftOf(const Vec2& a, const Vec2& b);

/// Intersection of `subject` (counter-clockwise, convex) with each half-plane in turn. Uses
/// `scratch` as the second buffer; `out` and `scratch` must be distinct from `subject`.
void clipByHalfPlanes(std::span<const Vec2> subject, std::span<const HalfPlane> half_planes,
                      std::vector<Vec2>& out, std::vector<Vec2>& scratch);

/// Intersection of two convex counter-clockwise polygons: `subject` clipped by the edges of `clip`
/// (Sutherland-Hodgman over a convex clipper). This produces the polygon of Keissar section 2.3:
/// the corners of each polygon inside the other and the crossings of their edges (eqs. 2.8-2.16);
/// nested polygons give the inner one, identical ones either, disjoint ones nothing, touching
/// ones a polygon of zero area. Edges of `clip` shorter than 1e-12 of its extent carry no usable
/// direction and are skipped. The result may hold repeated or collinear corners; its area and
/// centroid are unaffected.
void intersectConvex(std::span<const Vec2> subject, std::span<const Vec2> clip,
                     std::vector<Vec2>& out, std::vector<Vec2>& scratch);

struct AreaCentroid {
  double area = 0.0;             // signed: > 0 for a counter-clockwise polygon
  Vec2 centroid = Vec2::Zero();  // meaningless when area is 0
  double extent = 0.0;           // largest distance from the first corner to another corner
};

/// Area and area centroid of a polygon (Keissar eqs. 2.17-2.19), summed as a fan of triangles
/// about the first corner so that coordinates far from the origin lose no accuracy.
AreaCentroid areaCentroid(std::span<const Vec2> polygon);

}  // namespace polydem::geometry
