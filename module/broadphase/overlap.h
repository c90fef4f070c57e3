// Cheap candidate filters shared by the broad phase and the narrow phase: bounding spheres and
// axis-aligned boxes. Every broad-phase method decides a pair with withinReach(), so that the grid
// searches and the all-pairs reference take bit-identical decisions, touching pairs included.
#pragma once

#include <algorithm>
#include <limits>
#include <span>

#include "polydem/core/types.h"

namespace polydem::broadphase {

/// Zhao eq. (40) with a margin: centroid distance <= r_a + r_b + margin. Written on scalars in a
/// fixed order (no FMA, no reassociation) and symmetric in (a, b) bit for bit: swapping the pair
/// only negates the differences, and r_a + r_b is commutative.
inline bool withinReach(double ax, double ay, double az, double ar, double bx, double by, double bz,
                        double br, double margin) {
  const double dx = ax - bx;
  const double dy = ay - by;
  const double dz = az - bz;
  const double reach = ar + br + margin;
  return dx * dx + dy * dy + dz * dz <= reach * reach;
}

/// Two bounding spheres (centre, radius) within `margin` of touching; touching counts.
inline bool spheresOverlap(const Vec3& ca, double ra, const Vec3& cb, double rb,
                           double margin = 0.0) {
  return withinReach(ca.x(), ca.y(), ca.z(), ra, cb.x(), cb.y(), cb.z(), rb, margin);
}

/// Axis-aligned bounding box; an empty box has lo > hi.
struct Aabb {
  Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity());
  Vec3 hi = Vec3::Constant(-std::numeric_limits<double>::infinity());
};

/// The box of a body's world vertices (empty box for no vertices).
inline Aabb aabbOf(std::span<const Vec3> vertices) {
  Aabb box;
  for (const Vec3& v : vertices) {
    box.lo = box.lo.cwiseMin(v);
    box.hi = box.hi.cwiseMax(v);
  }
  return box;
}

/// Boxes within `margin` of each other on every axis; touching faces count as overlapping.
inline bool aabbsOverlap(const Aabb& a, const Aabb& b, double margin = 0.0) {
  for (int k = 0; k < 3; ++k) {
    if (a.lo[k] > b.hi[k] + margin || b.lo[k] > a.hi[k] + margin) return false;
  }
  return true;
}

}  // namespace polydem::broadphase
