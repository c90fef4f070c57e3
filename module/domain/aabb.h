// Axis-aligned bounding box: the domain, a block, or the reach of a particle.
#pragma once

#include <algorithm>
#include <cmath>

#include "polydem/core/types.h"

namespace polydem::domain {

/// A closed box [lo, hi] (all faces included). A box with hi < lo along some axis is empty.
struct Aabb {
  Vec3 lo = Vec3::Zero();
  Vec3 hi = Vec3::Zero();

  Aabb() = default;
  Aabb(const Vec3& lo_corner, const Vec3& hi_corner) : lo(lo_corner), hi(hi_corner) {}

  Vec3 extent() const { return hi - lo; }
  Vec3 center() const { return 0.5 * (lo + hi); }
  bool empty() const { return hi.x() < lo.x() || hi.y() < lo.y() || hi.z() < lo.z(); }
  /// 0 for an empty or flat box.
  double volume() const {
    if (empty()) return 0.0;
    const Vec3 e = extent();
    return e.x() * e.y() * e.z();
  }

  /// Closed test: points on a face count as inside. (Block ownership is half-open; see
  /// BlockForest::blockOf.)
  bool contains(const Vec3& x) const {
    return x.x() >= lo.x() && x.x() <= hi.x() && x.y() >= lo.y() && x.y() <= hi.y() &&
           x.z() >= lo.z() && x.z() <= hi.z();
  }
  /// Closed test: boxes that only touch intersect.
  bool intersects(const Aabb& other) const {
    return lo.x() <= other.hi.x() && other.lo.x() <= hi.x() && lo.y() <= other.hi.y() &&
           other.lo.y() <= hi.y() && lo.z() <= other.hi.z() && other.lo.z() <= hi.z();
  }

  /// Distance from `x` to the box along one axis: 0 inside the slab [lo, hi].
  double axisDistance(int axis, double x) const {
    return std::max({lo[axis] - x, 0.0, x - hi[axis]});
  }
  /// Squared Euclidean distance from `x` to the nearest point of the box; 0 inside.
  double squaredDistance(const Vec3& x) const {
    const double dx = axisDistance(0, x.x());
    const double dy = axisDistance(1, x.y());
    const double dz = axisDistance(2, x.z());
    return dx * dx + dy * dy + dz * dz;
  }
  /// Euclidean distance from `x` to the nearest point of the box; 0 inside.
  double distance(const Vec3& x) const { return std::sqrt(squaredDistance(x)); }

  /// The box grown by `margin` on every side (shrunk for a negative margin).
  Aabb inflated(double margin) const {
    const Vec3 m = Vec3::Constant(margin);
    return Aabb(lo - m, hi + m);
  }

  bool operator==(const Aabb& other) const { return lo == other.lo && hi == other.hi; }
};

}  // namespace polydem::domain
