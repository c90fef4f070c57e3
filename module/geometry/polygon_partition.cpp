#include "polydem/geometry/polygon_partition.h"

#include <algorithm>
#include <cmath>

#include "polydem/core/error.h"
#include "polydem/core/strings.h"
#include "polydem/core/tolerance.h"
#include "polydem/geometry/polygon.h"

namespace polydem::geometry {

namespace {

double polygonScale(const std::vector<Vec2>& p) {
  Vec2 lo = p[0], hi = p[0];
  for (const Vec2& v : p) {
    lo = lo.cwiseMin(v);
    hi = hi.cwiseMax(v);
  }
  return (hi - lo).norm();
}

// Whether the closed segments ab and cd share a point (touching counts).
bool segmentsMeet(const Vec2& a, const Vec2& b, const Vec2& c, const Vec2& d, double eps) {
  const double d1 = orient2(c, d, a), d2 = orient2(c, d, b);
  const double d3 = orient2(a, b, c), d4 = orient2(a, b, d);
  if (((d1 > eps && d2 < -eps) || (d1 < -eps && d2 > eps)) &&
      ((d3 > eps && d4 < -eps) || (d3 < -eps && d4 > eps))) {
    return true;
  }
  const auto onSegment = [eps](const Vec2& p, const Vec2& q, const Vec2& x, double o) {
    if (std::abs(o) > eps) return false;
    const double t = (x - p).dot(q - p), len2 = (q - p).squaredNorm();
    return t >= 0.0 && t <= len2;
  };
  return onSegment(c, d, a, d1) || onSegment(c, d, b, d2) || onSegment(a, b, c, d3) ||
         onSegment(a, b, d, d4);
}

// The polygon without repeated and straight corners, counter-clockwise; checked to be simple.
std::vector<Vec2> cleaned(const std::vector<Vec2>& polygon) {
  if (polygon.size() < 3) throw GeometryError("a polygon needs at least 3 corners");
  for (const Vec2& v : polygon) {
    if (!v.allFinite()) throw GeometryError("a polygon corner is not finite");
  }
  const double scale = polygonScale(polygon);
  const double point_tol = absTol(scale, RelTol::kPoint);
  const double area_tol = absTol(scale, RelTol::kPlane) * scale;  // twice a triangle's area
  const std::size_t n = polygon.size();
  for (std::size_t i = 0; i < n; ++i) {
    if ((polygon[i] - polygon[(i + 1) % n]).norm() <= point_tol) {
      throw GeometryError(cat("polygon corners ", i, " and ", (i + 1) % n, " coincide"));
    }
  }
  std::vector<Vec2> out;
  for (std::size_t i = 0; i < n; ++i) {
    const Vec2& prev = polygon[(i + n - 1) % n];
    const Vec2& next = polygon[(i + 1) % n];
    if (std::abs(orient2(prev, polygon[i], next)) > area_tol ||
        (polygon[i] - prev).dot(next - polygon[i]) < 0.0) {
      out.push_back(polygon[i]);
    }
  }
  if (out.size() < 3 || std::abs(twiceSignedArea(out)) <= area_tol) {
    throw GeometryError("the polygon has no area");
  }
  if (twiceSignedArea(out) < 0.0) std::reverse(out.begin(), out.end());
  const std::size_t m = out.size();
  for (std::size_t i = 0; i < m; ++i) {
    for (std::size_t j = i + 2; j < m; ++j) {
      if (i == 0 && j == m - 1) continue;  // neighbours through the closing edge
      if (segmentsMeet(out[i], out[(i + 1) % m], out[j], out[(j + 1) % m], area_tol)) {
        throw GeometryError(cat("polygon edges ", i, " and ", j, " cross or touch"));
      }
    }
  }
  return out;
}

// Ear clipping: triangles as corner indices, counter-clockwise. The ear taken is always the first
// one in corner order, so the result is the same on every machine.
std::vector<std::vector<int>> triangulate(const std::vector<Vec2>& p, double area_tol) {
  std::vector<int> left(p.size());
  for (std::size_t i = 0; i < p.size(); ++i) left[i] = static_cast<int>(i);
  std::vector<std::vector<int>> triangles;
  while (left.size() > 3) {
    const std::size_t m = left.size();
    bool clipped = false;
    for (std::size_t i = 0; i < m && !clipped; ++i) {
      const int a = left[(i + m - 1) % m], b = left[i], c = left[(i + 1) % m];
      if (orient2(p[a], p[b], p[c]) <= area_tol) continue;  // reflex or straight corner
      bool empty = true;
      for (int v : left) {
        if (v == a || v == b || v == c) continue;
        if (orient2(p[a], p[b], p[v]) >= -area_tol && orient2(p[b], p[c], p[v]) >= -area_tol &&
            orient2(p[c], p[a], p[v]) >= -area_tol) {
          empty = false;
          break;
        }
      }
      if (!empty) continue;
      triangles.push_back({a, b, c});
      left.erase(left.begin() + static_cast<std::ptrdiff_t>(i));
      clipped = true;
    }
    if (!clipped) throw GeometryError("cannot triangulate the polygon (is it simple?)");
  }
  triangles.push_back(left);
  return triangles;
}

// The piece `q` merged into `p` across their common edge, if the result is convex.
bool mergeConvex(std::vector<int>& p, const std::vector<int>& q, const std::vector<Vec2>& v,
                 double area_tol) {
  const std::size_t np = p.size(), nq = q.size();
  for (std::size_t i = 0; i < np; ++i) {
    const int a = p[i], b = p[(i + 1) % np];
    for (std::size_t j = 0; j < nq; ++j) {
      if (q[j] != b || q[(j + 1) % nq] != a) continue;
      // p from b round to a, then q's corners strictly between a and b.
      std::vector<int> merged;
      for (std::size_t k = 0; k < np; ++k) merged.push_back(p[(i + 1 + k) % np]);
      for (std::size_t k = 2; k < nq; ++k) merged.push_back(q[(j + k) % nq]);
      const std::size_t n = merged.size();
      for (std::size_t k = 0; k < n; ++k) {
        if (orient2(v[merged[(k + n - 1) % n]], v[merged[k]], v[merged[(k + 1) % n]]) < -area_tol) {
          return false;
        }
      }
      p = std::move(merged);
      return true;
    }
  }
  return false;
}

}  // namespace

double twiceSignedArea(const std::vector<Vec2>& polygon) {
  double a = 0.0;
  for (std::size_t i = 0; i < polygon.size(); ++i) {
    a += cross2(polygon[i] - polygon[0], polygon[(i + 1) % polygon.size()] - polygon[0]);
  }
  return a;
}

std::vector<std::vector<Vec2>> convexPartition(const std::vector<Vec2>& polygon) {
  const std::vector<Vec2> p = cleaned(polygon);
  const double scale = polygonScale(p);
  const double area_tol = absTol(scale, RelTol::kPlane) * scale;
  std::vector<std::vector<int>> pieces = triangulate(p, area_tol);
  // Hertel-Mehlhorn: merge neighbouring pieces while the union stays convex, in a fixed order.
  for (bool merged = true; merged;) {
    merged = false;
    for (std::size_t i = 0; i < pieces.size() && !merged; ++i) {
      for (std::size_t j = i + 1; j < pieces.size() && !merged; ++j) {
        if (mergeConvex(pieces[i], pieces[j], p, area_tol)) {
          pieces.erase(pieces.begin() + static_cast<std::ptrdiff_t>(j));
          merged = true;
        }
      }
    }
  }
  std::vector<std::vector<Vec2>> out;
  for (const auto& piece : pieces) {
    std::vector<Vec2> corners;
    for (int k : piece) corners.push_back(p[k]);
    out.push_back(std::move(corners));
  }
  return out;
}

}  // namespace polydem::geometry
