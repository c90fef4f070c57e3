#include "geometry/polygon.h"

#include <algorithm>
#include <cmath>

namespace polydem::geometry {

void convexHull(std::vector<Vec2>& points, std::vector<Vec2>& hull) {
  std::sort(points.begin(), points.end(), [](const Vec2& p, const Vec2& q) {
    return p.x() < q.x() || (p.x() == q.x() && p.y() < q.y());
  });
  const int n = static_cast<int>(points.size());
  hull.resize(2 * static_cast<std::size_t>(n) + 1);
  int k = 0;
  // Lower chain left to right, then upper chain right to left; a corner that does not turn left
  // (collinear or repeated) is dropped.
  for (int i = 0; i < n; ++i) {
    while (k >= 2 && orient2(hull[k - 2], hull[k - 1], points[i]) <= 0.0) --k;
    hull[k++] = points[i];
  }
  for (int i = n - 2, lower = k + 1; i >= 0; --i) {
    while (k >= lower && orient2(hull[k - 2], hull[k - 1], points[i]) <= 0.0) --k;
    hull[k++] = points[i];
  }
  hull.resize(n > 1 ? k - 1 : n);
}

bool containsPoint(std::span<const Vec2> polygon, const Vec2& p, double tolerance) {
  const std::size_t n = polygon.size();
  if (n == 0) return false;
  for (std::size_t i = 0; i < n; ++i) {
    const Vec2& a = polygon[i];
    const Vec2 edge = polygon[(i + 1) % n] - a;
    // Keissar eq. 2.8: the inward edge normal is n x edge; eq. 2.9: it must not point away from p.
    if (cross2(edge, p - a) < -tolerance * edge.norm()) return false;
  }
  return true;
}

void clipByHalfPlane(std::span<const Vec2> polygon, const HalfPlane& half_plane,
                     std::vector<Vec2>& out) {
  out.clear();
  const std::size_t n = polygon.size();
  if (n == 0) return;
  const Vec2* previous = &polygon[n - 1];
  double previous_value = half_plane.value(*previous);
  for (std::size_t i = 0; i < n; ++i) {
    const Vec2& current = polygon[i];
    const double value = half_plane.value(current);
    const bool inside = value <= 0.0, previous_inside = previous_value <= 0.0;
    if (inside != previous_inside) {
      // The edge crosses the line: the crossing at parameter t along previous -> current.
      const double t = previous_value / (previous_value - value);
      out.push_back(*previous + t * (current - *previous));
    }
    if (inside) out.push_back(current);
    previous = &current;
    previous_value = value;
  }
}

HalfPlane leftOf(const Vec2& a, const Vec2& b) {
  const Vec2 edge = b - a;
  const Vec2 outward(edge.y(), -edge.x());  // right of a -> b
  return {outward, outward.dot(a)};
}

void clipByHalfPlanes(std::span<const Vec2> subject, std::span<const HalfPlane> half_planes,
                      std::vector<Vec2>& out, std::vector<Vec2>& scratch) {
  // Alternate between the two buffers so that the last step writes into `out`.
  std::vector<Vec2>* target = (half_planes.size() % 2 == 1) ? &out : &scratch;
  std::span<const Vec2> current = subject;
  if (half_planes.empty()) {
    out.assign(subject.begin(), subject.end());
    return;
  }
  for (const HalfPlane& h : half_planes) {
    clipByHalfPlane(current, h, *target);
    current = *target;
    target = (target == &out) ? &scratch : &out;
    if (current.empty()) break;
  }
  if (current.data() != out.data()) out.assign(current.begin(), current.end());
}

void intersectConvex(std::span<const Vec2> subject, std::span<const Vec2> clip,
                     std::vector<Vec2>& out, std::vector<Vec2>& scratch) {
  const std::size_t n = clip.size();
  if (n < 3) {
    out.clear();  // a clip polygon without area holds no area
    return;
  }
  double extent = 0.0;
  for (const Vec2& q : clip) extent = std::max(extent, (q - clip[0]).norm());
  const double shortest = 1e-12 * extent;
  std::span<const Vec2> current = subject;
  std::vector<Vec2>* target = &out;
  bool clipped = false;
  for (std::size_t i = 0; i < n && !current.empty(); ++i) {
    const Vec2& a = clip[i];
    const Vec2& b = clip[(i + 1) % n];
    if (!((b - a).norm() > shortest)) continue;
    clipByHalfPlane(current, leftOf(a, b), *target);
    current = *target;
    target = (target == &out) ? &scratch : &out;
    clipped = true;
  }
  if (!clipped) {
    out.clear();  // every corner of `clip` at one point: no area
  } else if (current.data() != out.data()) {
    out.assign(current.begin(), current.end());
  }
}

AreaCentroid areaCentroid(std::span<const Vec2> polygon) {
  AreaCentroid r;
  const std::size_t n = polygon.size();
  if (n == 0) return r;
  const Vec2& p0 = polygon[0];
  r.centroid = p0;
  for (std::size_t k = 1; k < n; ++k) r.extent = std::max(r.extent, (polygon[k] - p0).norm());
  if (n < 3) return r;
  // Keissar eqs. 2.17-2.18 with the origin moved to the first corner: the terms of the first and
  // last edges vanish and the rest is a fan of triangles (p0, p_k, p_k+1).
  double twice_area = 0.0;
  Vec2 moment = Vec2::Zero();
  for (std::size_t k = 1; k + 1 < n; ++k) {
    const Vec2 d1 = polygon[k] - p0, d2 = polygon[k + 1] - p0;
    const double c = cross2(d1, d2);
    twice_area += c;
    moment += c * (d1 + d2);
  }
  r.area = 0.5 * twice_area;
  if (twice_area != 0.0) r.centroid = p0 + moment / (3.0 * twice_area);  // eq. 2.19
  return r;
}

}  // namespace polydem::geometry
