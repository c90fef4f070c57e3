// Clipping a convex polygon in space by half-spaces, without allocation once warm.
//
// A convex polygon (its corners in order, all in one plane) keeps its part where an affine
// function w.x + c is <= 0 (Sutherland-Hodgman, one half-space at a time). The affine function
// need not be a unit-normal plane: the potential kernels clip by {phi_j <= phi_k}, the difference
// of two scaled plane distances. Used by the distance-potential and FDEM kernels (contact/).
#pragma once

#include <span>
#include <vector>

#include "core/types.h"

namespace polydem::geometry {

/// Holds one polygon and clips it in place; the buffers keep their capacity between polygons, so
/// a clipper reused for every pair allocates only while it grows to the largest polygon seen.
class ConvexPolygonClipper {
 public:
  /// Starts from the polygon with corners `points[loop[i]]` (convex, planar, in order).
  void assign(std::span<const Vec3> points, std::span<const int> loop) {
    poly_.clear();
    for (int i : loop) poly_.push_back(points[i]);
  }
  void assign(std::span<const Vec3> corners) { poly_.assign(corners.begin(), corners.end()); }

  /// Keeps the part where w.x + c <= 0. Corners with w.x + c == 0 are kept and no new corner is
  /// made next to them, so a polygon lying on the boundary survives whole. Returns false when no
  /// corner is left (the polygon was entirely outside).
  bool clip(const Vec3& w, double c) {
    const std::size_t n = poly_.size();
    if (n == 0) return false;
    h_.resize(n);
    bool any_out = false, any_in = false;
    for (std::size_t i = 0; i < n; ++i) {
      h_[i] = w.dot(poly_[i]) + c;
      if (h_[i] > 0.0) {
        any_out = true;
      } else {
        any_in = true;
      }
    }
    if (!any_out) return true;
    if (!any_in) {
      poly_.clear();
      return false;
    }
    next_.clear();
    for (std::size_t i = 0; i < n; ++i) {
      const std::size_t j = i + 1 == n ? 0 : i + 1;
      const double hi = h_[i], hj = h_[j];
      if (hi <= 0.0) next_.push_back(poly_[i]);
      if ((hi < 0.0 && hj > 0.0) || (hi > 0.0 && hj < 0.0)) {
        next_.push_back(poly_[i] + (hi / (hi - hj)) * (poly_[j] - poly_[i]));
      }
    }
    poly_.swap(next_);
    return true;
  }

  const std::vector<Vec3>& polygon() const { return poly_; }

 private:
  std::vector<Vec3> poly_, next_;
  std::vector<double> h_;
};

}  // namespace polydem::geometry
