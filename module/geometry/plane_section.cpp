#include "polydem/geometry/plane_section.h"

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
  points.resize(heights.size() + shape.edges().size());
  Vec2* out = points.data();
  std::size_t count = 0;
  // Vertices on the plane belong to the section; an edge from one of them is not crossed.
  for (std::size_t i = 0; i < heights.size(); ++i) {
    if (heights[i] == 0.0) out[count++] = frame.project(world_vertices[i]);
  }
  for (const Edge& e : shape.edges()) {
    const double h0 = heights[e.v0], h1 = heights[e.v1];
    if (!((h0 < 0.0 && h1 > 0.0) || (h0 > 0.0 && h1 < 0.0))) continue;
    // Keissar eq. 2.7 with P1 = v0, P2 = v1: u = h0 / (h0 - h1); eq. 2.5 gives the point, taken
    // relative to the frame's origin.
    const double t = h0 / (h0 - h1);
    const Vec3 d0 = world_vertices[e.v0] - frame.origin;
    const Vec3 d = d0 + t * (world_vertices[e.v1] - world_vertices[e.v0]);
    out[count++] = Vec2(frame.u.dot(d), frame.v.dot(d));
  }
  points.resize(count);
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
  const auto& faces = shape.faces();
  auto add = [&](int f) {
    // The face's plane n . (x - x_f) <= 0 restricted to the plane: with x = origin + y1 u + y2 v,
    // (n.u, n.v) . y <= n . (x_f - origin).
    const Vec3 n = rotation * faces[f].normal;
    const Vec2 g(n.dot(frame.u), n.dot(frame.v));
    if (!(g.squaredNorm() > 0.0)) return;
    half_planes.push_back({g, n.dot(world_vertices[faces[f].vertices[0]] - frame.origin)});
  };
  // Going round a face counter-clockwise, the heights pass from negative to non-negative exactly
  // once if the face has vertices of both kinds: the face is taken at that edge, so each face
  // meeting the plane comes once, and faces wholly above or below never.
  for (const Edge& e : shape.edges()) {
    const double h0 = heights[e.v0], h1 = heights[e.v1];
    if (h0 < 0.0 && h1 >= 0.0) add(e.f0);  // e runs v0 -> v1 in f0
    if (h1 < 0.0 && h0 >= 0.0) add(e.f1);  // and v1 -> v0 in f1
  }
  return true;
}

}  // namespace polydem::geometry
