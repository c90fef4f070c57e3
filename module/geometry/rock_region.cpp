// The regions a rock mass is cut from (rock_mass.h): a box, a convex polyhedron, a slope profile.
#include <cmath>

#include "polydem/core/error.h"
#include "polydem/geometry/polygon_partition.h"
#include "polydem/geometry/rock_mass.h"
#include "polydem/geometry/shapes.h"

namespace polydem::geometry {

namespace {

RockRegion fromPieces(std::vector<ConvexPolyhedron> pieces) {
  RockRegion r;
  r.pieces = std::move(pieces);
  for (const ConvexPolyhedron& p : r.pieces) r.volume += p.volume();
  return r;
}

}  // namespace

RockRegion boxRegion(const Vec3& lo, const Vec3& hi) {
  return fromPieces({ConvexPolyhedron::fromPoints(shapes::box(lo, hi))});
}

RockRegion polyhedronRegion(const std::vector<Vec3>& points) {
  return fromPieces({ConvexPolyhedron::fromPoints(points)});
}

RockRegion profileRegion(const std::vector<Vec2>& profile, double y_min, double y_max) {
  if (!(y_max > y_min) || !std::isfinite(y_min) || !std::isfinite(y_max)) {
    throw GeometryError("a slope profile needs y_min < y_max");
  }
  std::vector<ConvexPolyhedron> pieces;
  for (const std::vector<Vec2>& polygon : convexPartition(profile)) {
    std::vector<Vec3> base;
    for (const Vec2& p : polygon) base.emplace_back(p.x(), y_min, p.y());
    pieces.push_back(
        ConvexPolyhedron::fromPoints(shapes::prism(base, Vec3(0.0, y_max - y_min, 0.0))));
  }
  return fromPieces(std::move(pieces));
}

}  // namespace polydem::geometry
