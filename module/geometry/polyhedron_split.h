// What ConvexPolyhedron::split would do with a plane, decided without making the parts: a rock
// mass offers every block to every plane, and most planes miss most blocks.
#pragma once

#include "polydem/geometry/convex_polyhedron.h"

namespace polydem::geometry {

/// -1 if split(plane) would return only a part below, +1 only above, 0 both (the plane cuts).
int splitSide(const ConvexPolyhedron& poly, const Plane& plane);

}  // namespace polydem::geometry
