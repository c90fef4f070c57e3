// The resultant of a pressure that varies linearly in space, acting on a planar polygon where it
// is positive: the hydrostatic water pressure p = gamma_w (z_surface(x, y) - z) on a block's face
// below a plane phreatic surface. The polygon is clipped at p = 0; p is linear on what is left,
// so force and moment follow exactly from the clipped polygon's triangles (the integral of a
// linear function, and of a product of two, over a triangle), with no quadrature.
#pragma once

#include <span>

#include "polydem/core/types.h"

namespace polydem::geometry {

/// p(x) = value + gradient . (x - origin) [Pa].
struct LinearPressure {
  Vec3 origin = Vec3::Zero();
  double value = 0.0;            // Pa at origin
  Vec3 gradient = Vec3::Zero();  // Pa/m
};

struct PressureResultant {
  Vec3 force = Vec3::Zero();   // N, on the body the face bounds
  Vec3 moment = Vec3::Zero();  // N m, about LinearPressure::origin
  double wetted_area = 0.0;    // m^2 of the polygon where p > 0
  /// The integral of p over the polygon (N): |force| for a face the pressure wets.
  double load = 0.0;
};

/// The positive part of `pressure` on the convex planar polygon points[polygon[0]],
/// points[polygon[1]], ..., counter-clockwise seen from the side its outward unit `normal` points
/// to (a Face of a ConvexPolyhedron), pushing against the normal (into the body):
/// force = -normal * integral of max(p, 0) dA, moment = integral of (x - origin) x dF.
/// Allocates nothing.
PressureResultant pressureResultant(std::span<const Vec3> points, std::span<const int> polygon,
                                    const Vec3& normal, const LinearPressure& pressure);

}  // namespace polydem::geometry
