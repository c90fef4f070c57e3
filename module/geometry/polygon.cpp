#include "polydem/geometry/polygon.h"

#include <algorithm>
#include <cmath>

namespace polydem::geometry {

namespace {

bool lexicographic(const Vec2& p, const Vec2& q) {
  return p.x() < q.x() || (p.x() == q.x() && p.y() < q.y());
}

/// Sorts by x, then y. Sections of polyhedra have a handful of corners: insertion sort then.
void sortLexicographic(std::vector<Vec2>& points) {
  if (points.size() > 16) {
    std::sort(points.begin(), points.end(), lexicographic);
    return;
  }
  for (std::size_t i = 1; i < points.size(); ++i) {
    const Vec2 p = points[i];
    std::size_t j = i;
    for (; j > 0 && lexicographic(p, points[j - 1]); --j) points[j] = points[j - 1];
    points[j] = p;
  }
}

}  // namespace

void convexHull(std::vector<Vec2>& points, std::vector<Vec2>& hull) {
  sortLexicographic(points);
  const int n = static_cast<int>(points.size());
  hull.resize(2 * static_cast<std::size_t>(n) + 1);
  Vec2* h = hull.data();
  int k = 0;
  // Lower chain left to right, then upper chain right to left; a corner that does not turn left
  // (collinear or repeated) is dropped.
  for (int i = 0; i < n; ++i) {
    while (k >= 2 && orient2(h[k - 2], h[k - 1], points[i]) <= 0.0) --k;
    h[k++] = points[i];
  }
  for (int i = n - 2, lower = k + 1; i >= 0; --i) {
    while (k >= lower && orient2(h[k - 2], h[k - 1], points[i]) <= 0.0) --k;
    h[k++] = points[i];
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

std::size_t clipByHalfPlane(std::span<const Vec2> polygon, const HalfPlane& half_plane, Vec2* out) {
  const std::size_t n = polygon.size();
  if (n == 0) return 0;
  std::size_t count = 0;
  const Vec2* previous = &polygon[n - 1];
  double previous_value = half_plane.value(*previous);
  for (std::size_t i = 0; i < n; ++i) {
    const Vec2& current = polygon[i];
    const double value = half_plane.value(current);
    const bool inside = value <= 0.0;
    if (inside != (previous_value <= 0.0)) {
      // The edge crosses the line: the crossing at parameter t along previous -> current.
      const double t = previous_value / (previous_value - value);
      out[count++] = *previous + t * (current - *previous);
    }
    if (inside) out[count++] = current;
    previous = &current;
    previous_value = value;
  }
  return count;
}

HalfPlane leftOf(const Vec2& a, const Vec2& b) {
  const Vec2 edge = b - a;
  const Vec2 outward(edge.y(), -edge.x());  // right of a -> b
  return {outward, outward.dot(a)};
}

namespace {

/// Sutherland-Hodgman step with the half-plane's values at the corners already computed.
std::size_t clipWithValues(std::span<const Vec2> polygon, const double* value, Vec2* out) {
  const std::size_t n = polygon.size();
  std::size_t count = 0;
  std::size_t previous = n - 1;
  for (std::size_t i = 0; i < n; ++i) {
    const bool inside = value[i] <= 0.0;
    if (inside != (value[previous] <= 0.0)) {
      const double t = value[previous] / (value[previous] - value[i]);
      out[count++] = polygon[previous] + t * (polygon[i] - polygon[previous]);
    }
    if (inside) out[count++] = polygon[i];
    previous = i;
  }
  return count;
}

/// Clips `subject` by half-planes produced one at a time by next(h) (false when there are no
/// more), alternating between `out` and `scratch` (each sized for the largest possible result:
/// every half-plane adds at most one corner), and leaves the result in `out`.
template <typename Next>
void clipSequence(std::span<const Vec2> subject, std::size_t max_planes, Next next,
                  std::vector<Vec2>& out, std::vector<Vec2>& scratch) {
  const std::size_t capacity = subject.size() + max_planes;
  out.resize(capacity);
  scratch.resize(capacity);
  std::span<const Vec2> current = subject;
  Vec2* target = out.data();
  HalfPlane h;
  std::size_t count = subject.size();
  constexpr std::size_t kSmall = 64;
  double value[kSmall];
  while (count > 0 && next(h)) {
    if (count <= kSmall) {
      // Most half-planes of a contact leave the polygon whole: then nothing is written.
      bool inside = true;
      for (std::size_t i = 0; i < count; ++i) {
        value[i] = h.value(current[i]);
        inside = inside && value[i] <= 0.0;
      }
      if (inside) continue;
      count = clipWithValues(current, value, target);
    } else {
      count = clipByHalfPlane(current, h, target);
    }
    current = {target, count};
    target = (target == out.data()) ? scratch.data() : out.data();
  }
  if (current.data() != out.data()) std::copy(current.begin(), current.end(), out.begin());
  out.resize(count);
}

}  // namespace

void clipByHalfPlanes(std::span<const Vec2> subject, std::span<const HalfPlane> half_planes,
                      std::vector<Vec2>& out, std::vector<Vec2>& scratch) {
  std::size_t i = 0;
  clipSequence(
      subject, half_planes.size(),
      [&](HalfPlane& h) {
        if (i == half_planes.size()) return false;
        h = half_planes[i++];
        return true;
      },
      out, scratch);
}

void intersectConvex(std::span<const Vec2> subject, std::span<const Vec2> clip,
                     std::vector<Vec2>& out, std::vector<Vec2>& scratch) {
  const std::size_t n = clip.size();
  double extent = 0.0;
  for (const Vec2& q : clip) extent = std::max(extent, (q - clip[0]).norm());
  if (n < 3 || !(extent > 0.0)) {
    out.clear();  // a clip polygon without area holds no area
    return;
  }
  const double shortest = 1e-12 * extent;
  std::size_t i = 0;
  clipSequence(
      subject, n,
      [&](HalfPlane& h) {
        for (; i < n; ++i) {
          const Vec2& a = clip[i];
          const Vec2& b = clip[(i + 1) % n];
          if ((b - a).norm() > shortest) {
            h = leftOf(a, b);
            ++i;
            return true;
          }
        }
        return false;
      },
      out, scratch);
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
