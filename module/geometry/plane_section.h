// The section of a placed convex polyhedron by a plane (Keissar section 2.3, eqs. 2.3-2.7): the
// polygon where the plane cuts it, in the 2D coordinates of a frame of the plane, and the
// half-planes that bound that polygon (the traces of the faces the plane cuts).
//
// A placed polyhedron is its shape (topology, body-frame normals) with its world vertices (in the
// shape's order) and the rotation from body to world frame.
#pragma once

#include <span>
#include <vector>

#include "polydem/core/types.h"
#include "polydem/geometry/convex_polyhedron.h"
#include "polydem/geometry/polygon.h"

namespace polydem::geometry {

/// An orthonormal frame (u, v, normal), right-handed, on the plane through `origin` with unit
/// `normal`: counter-clockwise in (u, v) is counter-clockwise seen from the side `normal` points
/// to. Place the origin near the region of interest: 2D coordinates are relative to it.
struct PlaneFrame {
  Vec3 origin = Vec3::Zero();
  Vec3 normal = Vec3::UnitZ();
  Vec3 u = Vec3::UnitX(), v = Vec3::UnitY();

  /// The frame with the given unit normal and origin; u is built from the coordinate axis least
  /// aligned with the normal.
  static PlaneFrame make(const Vec3& unit_normal, const Vec3& origin);

  /// Height above the plane (Keissar eq. 2.3 up to the sign).
  double height(const Vec3& x) const { return normal.dot(x - origin); }
  Vec2 project(const Vec3& x) const {
    const Vec3 d = x - origin;
    return {u.dot(d), v.dot(d)};
  }
  Vec3 lift(const Vec2& y) const { return origin + y.x() * u + y.y() * v; }
};

/// Heights of the world vertices above the plane, one per vertex.
void planeHeights(std::span<const Vec3> world_vertices, const PlaneFrame& frame,
                  std::vector<double>& heights);

/// The section polygon, counter-clockwise in the frame: where the edges with one end strictly on
/// either side cross the plane (Keissar eqs. 2.5-2.7) plus the vertices on the plane, ordered by
/// their convex hull (which drops repeats). Fewer than three corners when the plane misses the
/// polyhedron or only touches it. `points` is scratch.
void sectionPolygon(const ConvexPolyhedron& shape, std::span<const Vec3> world_vertices,
                    const PlaneFrame& frame, std::span<const double> heights,
                    std::vector<Vec2>& polygon, std::vector<Vec2>& points);

/// The half-planes, in the frame, of the faces the plane meets (vertices below it and others on
/// or above it), each once: their intersection is the section polygon. Each is taken from the
/// face's own plane, so it is exact even where the section has a tiny edge (the plane passing
/// near a vertex), unlike an edge through two nearly equal corners. `rotation` turns body-frame
/// normals into world ones. Returns false when the plane misses the polyhedron (all vertices on
/// one side) or only touches it.
bool sectionHalfPlanes(const ConvexPolyhedron& shape, std::span<const Vec3> world_vertices,
                       const Mat3& rotation, const PlaneFrame& frame,
                       std::span<const double> heights, std::vector<HalfPlane>& half_planes);

}  // namespace polydem::geometry
