#include "geometry/plane_section.h"

#include <algorithm>
#include <cmath>

namespace polydem::geometry {

PlaneFrame PlaneFrame::make(const Vec3& unit_normal, const Vec3& origin) {
  PlaneFrame f;
  f.origin = origin;
  f.normal = unit_normal;
  int k = 0;
  for (int m = 1; m < 3; ++m) {
    if (std::abs(unit_normal[m]) < std::abs(unit_normal[k])) k = m;
  }
  f.u = Vec3::Unit(k).cross(unit_normal).normalized();
  f.v = unit_normal.cross(f.u);
  return f;
}

void planeHeights(std::span<const Vec3> world_vertices, const PlaneFrame& frame,
                  std::vector<double>& heights) {
  heights.resize(world_vertices.size());
  for (std::size_t i = 0; i < world_vertices.size(); ++i) {
    heights[i] = frame.height(world_vertices[i]);
  }
}

void sectionPolygon(const ConvexPolyhedron& shape, std::span<const Vec3> world_vertices,
                    const PlaneFrame& frame, std::span<const double> heights,
                    std::vector<Vec2>& polygon, std::vector<Vec2>& points) {
  points.clear();
  // Vertices on the plane belong to the section; an edge from one of them is not crossed.
  for (std::size_t i = 0; i < heights.size(); ++i) {
    if (heights[i] == 0.0) points.push_back(frame.project(world_vertices[i]));
  }
  for (const Edge& e : shape.edges()) {
    const double h0 = heights[e.v0], h1 = heights[e.v1];
    if (!((h0 < 0.0 && h1 > 0.0) || (h0 > 0.0 && h1 < 0.0))) continue;
    // Keissar eq. 2.7 with P1 = v0, P2 = v1: u = h0 / (h0 - h1); eq. 2.5 gives the point, taken
    // relative to the frame's origin.
    const double t = h0 / (h0 - h1);
    const Vec3 d0 = world_vertices[e.v0] - frame.origin;
    const Vec3 d = d0 + t * (world_vertices[e.v1] - world_vertices[e.v0]);
    points.emplace_back(frame.u.dot(d), frame.v.dot(d));
  }
  convexHull(points, polygon);
}

bool sectionHalfPlanes(const ConvexPolyhedron& shape, std::span<const Vec3> world_vertices,
                       const Mat3& rotation, const PlaneFrame& frame,
                       std::span<const double> heights, std::vector<HalfPlane>& half_planes) {
  half_planes.clear();
  bool below = false, above = false;
  for (double h : heights) {
    below = below || h < 0.0;
    above = above || h > 0.0;
  }
  if (!(below && above)) return false;
  for (const Face& face : shape.faces()) {
    double lo = heights[face.vertices[0]], hi = lo;
    for (int v : face.vertices) {
      lo = std::min(lo, heights[v]);
      hi = std::max(hi, heights[v]);
    }
    if (!(lo <= 0.0 && hi >= 0.0 && lo < hi)) continue;
    // The face's plane n . (x - x_f) <= 0 restricted to the plane: with x = origin + y1 u + y2 v,
    // (n.u, n.v) . y <= n . (x_f - origin).
    const Vec3 n = rotation * face.normal;
    const Vec2 g(n.dot(frame.u), n.dot(frame.v));
    if (!(g.squaredNorm() > 0.0)) continue;
    half_planes.push_back({g, n.dot(world_vertices[face.vertices[0]] - frame.origin)});
  }
  return true;
}

}  // namespace polydem::geometry
