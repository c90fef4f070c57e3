// Clipping a convex polygon in space by half-spaces, without allocation once warm.
//
// A convex polygon (its corners in order, all in one plane) keeps its part where an affine
// function w.x + c is <= 0 (Sutherland-Hodgman, one half-space at a time), in space or in the 2D
// coordinates of its plane. The affine function need not be a unit-normal plane. Used by the
// potential kernels and the overlap centroid (contact/).
#pragma once

#include <algorithm>
#include <span>
#include <vector>

#include "polydem/core/types.h"

namespace polydem::geometry {

/// Holds one polygon and clips it in place; the buffers keep their capacity between polygons, so
/// a clipper reused for every pair allocates only while it grows to the largest polygon seen.
/// `Point` is Vec3 (a polygon in space) or Vec2 (a polygon in the coordinates of its plane).
template <class Point>
class BasicConvexPolygonClipper {
 public:
  /// Starts from the polygon with corners `points[loop[i]]` (convex, planar, in order).
  void assign(std::span<const Point> points, std::span<const int> loop) {
    reserve(loop.size());
    n_ = 0;
    for (int i : loop) poly_[n_++] = points[i];
  }
  void assign(std::span<const Point> corners) {
    reserve(corners.size());
    n_ = corners.size();
    std::copy(corners.begin(), corners.end(), poly_.begin());
  }

  /// Keeps the part where w.x + c <= 0. Corners with w.x + c == 0 are kept and no new corner is
  /// made next to them, so a polygon lying on the boundary survives whole. Returns false when no
  /// corner is left (the polygon was entirely outside).
  bool clip(const Point& w, double c) {
    const std::size_t n = n_;
    if (n == 0) return false;
    reserve(n + 1);  // a convex polygon cut by a line gains at most one corner
    double* h = h_.data();
    const Point* poly = poly_.data();
    bool any_out = false, any_in = false;
    for (std::size_t i = 0; i < n; ++i) {
      h[i] = w.dot(poly[i]) + c;
      any_out = any_out || h[i] > 0.0;
      any_in = any_in || !(h[i] > 0.0);
    }
    if (!any_out) return true;
    if (!any_in) {
      n_ = 0;
      return false;
    }
    Point* out = next_.data();
    std::size_t m = 0;
    for (std::size_t i = 0; i < n; ++i) {
      const std::size_t j = i + 1 == n ? 0 : i + 1;
      const double hi = h[i], hj = h[j];
      if (hi <= 0.0) out[m++] = poly[i];
      if ((hi < 0.0 && hj > 0.0) || (hi > 0.0 && hj < 0.0)) {
        out[m++] = poly[i] + (hi / (hi - hj)) * (poly[j] - poly[i]);
      }
    }
    poly_.swap(next_);
    n_ = m;
    return true;
  }

  std::span<const Point> polygon() const { return {poly_.data(), n_}; }

 private:
  // The buffers only grow (their size is their capacity; n_ is the polygon's size).
  void reserve(std::size_t n) {
    if (poly_.size() >= n) return;
    const std::size_t size = 2 * n + 8;
    poly_.resize(size);
    next_.resize(size);
    h_.resize(size);
  }

  std::vector<Point> poly_, next_;
  std::vector<double> h_;
  std::size_t n_ = 0;
};

using ConvexPolygonClipper = BasicConvexPolygonClipper<Vec3>;

}  // namespace polydem::geometry
