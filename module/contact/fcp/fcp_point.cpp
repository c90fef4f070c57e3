// The FCP contact point from the contact features of the common plane, without the IPM (see
// fcpFeaturePoint in fcp.h). The features are the closest-vertex sets of the plane, projected on
// it; the in-plane point depends on their kinds, the height is the middle of the overlap.
#include <algorithm>
#include <cmath>

#include "polydem/contact/fcp/fcp.h"
#include "polydem/contact/fcp/fcp_detail.h"
#include "polydem/geometry/polygon.h"

namespace polydem::contact {

namespace {

using geometry::cross2;

struct PointScratch {
  std::vector<int> band_a, band_b;
  std::vector<Vec2> points_a, points_b, hull_a, hull_b, clipped, spare;
};

PointScratch& pointScratch() {
  thread_local PointScratch s;
  return s;
}

/// An in-plane point and whether the two features overlap there (within the tolerance).
struct Spot {
  Vec2 p = Vec2::Zero();
  bool overlap = true;
};

Vec2 mean(std::span<const Vec2> points) {
  Vec2 m = Vec2::Zero();
  for (const Vec2& p : points) m += p;
  return m / static_cast<double>(points.size());
}

/// Closest point of segment [s0, s1] to x.
Vec2 closestOnSegment(const Vec2& s0, const Vec2& s1, const Vec2& x) {
  const Vec2 d = s1 - s0;
  const double t = std::clamp(d.dot(x - s0) / d.squaredNorm(), 0.0, 1.0);
  return s0 + t * d;
}

/// Vertex against a vertex, an edge or a face: the vertex (two vertices: their middle).
Spot vertexAgainst(const Vec2& v, std::span<const Vec2> other, double tol) {
  if (other.size() == 1) return {0.5 * (v + other[0]), (v - other[0]).norm() <= tol};
  if (other.size() == 2) return {v, (closestOnSegment(other[0], other[1], v) - v).norm() <= tol};
  return {v, geometry::containsPoint(other, v, tol)};
}

/// Two edges: where they cross; closest points of the segments when they miss each other;
/// parallel edges: the middle of the overlap of their projections on the common line.
Spot edgeEdge(std::span<const Vec2> s, std::span<const Vec2> t, double tol) {
  const Vec2 ds = s[1] - s[0], dt = t[1] - t[0];
  const double cross = cross2(ds, dt);
  if (std::abs(cross) > kFcpParallelSine * ds.norm() * dt.norm()) {
    const Vec2 r = t[0] - s[0];
    const double u = cross2(r, dt) / cross, w = cross2(r, ds) / cross;
    const double slack_s = tol / ds.norm(), slack_t = tol / dt.norm();
    if (u >= -slack_s && u <= 1.0 + slack_s && w >= -slack_t && w <= 1.0 + slack_t) {
      return {s[0] + u * ds, true};
    }
    // The segments miss each other: the closest pair among the ends projected on the other one.
    Vec2 best_p = s[0], best_q = closestOnSegment(t[0], t[1], s[0]);
    const auto consider = [&](const Vec2& p, const Vec2& q) {
      if ((p - q).squaredNorm() < (best_p - best_q).squaredNorm()) {
        best_p = p;
        best_q = q;
      }
    };
    consider(s[1], closestOnSegment(t[0], t[1], s[1]));
    consider(closestOnSegment(s[0], s[1], t[0]), t[0]);
    consider(closestOnSegment(s[0], s[1], t[1]), t[1]);
    return {0.5 * (best_p + best_q), false};
  }
  const Vec2 dir = ds.normalized(), perp(-dir.y(), dir.x());
  const auto interval = [&](std::span<const Vec2> e) {
    const double p = dir.dot(e[0]), q = dir.dot(e[1]);
    return std::pair{std::min(p, q), std::max(p, q)};
  };
  const auto [s_lo, s_hi] = interval(s);
  const auto [t_lo, t_hi] = interval(t);
  const double lo = std::max(s_lo, t_lo), hi = std::min(s_hi, t_hi);
  const double across_s = perp.dot(s[0]), across_t = perp.dot(t[0]);
  const Vec2 p = 0.5 * (lo + hi) * dir + 0.5 * (across_s + across_t) * perp;
  return {p, lo <= hi + tol && std::abs(across_s - across_t) <= tol};
}

/// An edge against a face polygon: the middle of the part of the edge inside the polygon
/// (Cyrus-Beck clipping by the polygon's edges).
Spot edgeFace(std::span<const Vec2> s, std::span<const Vec2> polygon, double tol) {
  const Vec2 d = s[1] - s[0];
  double lo = 0.0, hi = 1.0;
  const std::size_t n = polygon.size();
  for (std::size_t i = 0; i < n; ++i) {
    const Vec2& a = polygon[i];
    const Vec2 edge = polygon[(i + 1) % n] - a;
    // Left of the edge (inside) is cross2(edge, x - a) >= 0; `tol` widens the polygon.
    const double slack = tol * edge.norm();
    const double f0 = cross2(edge, s[0] - a) + slack, f1 = cross2(edge, s[1] - a) + slack;
    if (f0 < 0.0 && f1 < 0.0) {
      lo = 1.0;
      hi = 0.0;
      break;
    }
    if (f0 < 0.0) lo = std::max(lo, f0 / (f0 - f1));
    if (f1 < 0.0) hi = std::min(hi, f0 / (f0 - f1));
  }
  if (lo > hi) return {0.5 * (0.5 * (s[0] + s[1]) + mean(polygon)), false};
  return {s[0] + 0.5 * (lo + hi) * d, true};
}

/// Two face polygons: the area centroid of their intersection (Keissar eqs. 2.17-2.19).
Spot faceFace(std::span<const Vec2> p, std::span<const Vec2> q, double tol, PointScratch& w) {
  geometry::intersectConvex(p, q, w.clipped, w.spare);
  if (w.clipped.empty()) return {0.5 * (mean(p) + mean(q)), false};
  const geometry::AreaCentroid m = geometry::areaCentroid(w.clipped);
  // Touching along an edge or at a corner (no width): the middle of what is shared.
  if (!(m.area > tol * m.extent)) return {mean(w.clipped), true};
  return {m.centroid, true};
}

Spot featureSpot(std::span<const Vec2> fa, std::span<const Vec2> fb, double tol, PointScratch& w) {
  if (fa.size() == 1) return vertexAgainst(fa[0], fb, tol);
  if (fb.size() == 1) return vertexAgainst(fb[0], fa, tol);
  if (fa.size() == 2 && fb.size() == 2) return edgeEdge(fa, fb, tol);
  if (fa.size() == 2) return edgeFace(fa, fb, tol);
  if (fb.size() == 2) return edgeFace(fb, fa, tol);
  return faceFace(fa, fb, tol, w);
}

}  // namespace

Vec3 fcpFeaturePoint(const Body& a, const Body& b, const CommonPlane& plane, Status* status) {
  PointScratch& w = pointScratch();
  const double tol = FcpTolerance::kBand * fcp_detail::lengthScale(a, b);
  const Vec3& n = plane.normal;
  fcp_detail::collectBand(a, -n, plane.vertex_a, -plane.level_a - tol, w.band_a);
  fcp_detail::collectBand(b, n, plane.vertex_b, plane.level_b - tol, w.band_b);
  // Coordinates relative to a closest vertex of A, which lies on level_a.
  const auto frame = geometry::PlaneFrame::make(n, a.vertices[plane.vertex_a]);
  w.points_a.clear();
  for (int v : w.band_a) w.points_a.push_back(frame.project(a.vertices[v]));
  w.points_b.clear();
  for (int v : w.band_b) w.points_b.push_back(frame.project(b.vertices[v]));
  geometry::convexHull(w.points_a, w.hull_a);
  geometry::convexHull(w.points_b, w.hull_b);
  const Spot spot = featureSpot(w.hull_a, w.hull_b, tol, w);
  if (status != nullptr) *status = spot.overlap ? Status::kOk : Status::kDegenerate;
  return frame.lift(spot.p) + 0.5 * (plane.level_b - plane.level_a) * n;
}

}  // namespace polydem::contact
