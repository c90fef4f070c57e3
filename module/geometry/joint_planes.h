// Joint sets and single planes of a rock mass as geologists give them (dip, dip direction,
// spacing), turned into the planes that cut it (rock_mass.h).
//
// Frame: x east, y north, z up. Dip direction is the azimuth of the down-dip line, clockwise
// from north (90 = dipping towards east); dip is the angle below the horizontal, in [0, 90].
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "polydem/core/types.h"
#include "polydem/geometry/convex_polyhedron.h"

namespace polydem::geometry {

/// The upward unit normal of a plane of this dip and dip direction (degrees): (sin dip sin dd,
/// sin dip cos dd, cos dip). A vertical plane's normal points along its dip direction.
Vec3 normalFromDip(double dip_deg, double dip_direction_deg);

/// A set of parallel joints (3DEC's jset): planes `spacing` apart with the normal of (dip, dip
/// direction); plane 0 passes through origin + offset * normal. Optional jitter from `seed`, the
/// same on every machine: each gap between neighbouring planes is spacing * (1 + s u) with u
/// uniform in [-1, 1) and s = spacing_jitter, and each plane's normal is turned by up to
/// orientation_jitter degrees in a random direction, or (fisher_k > 0) turned to a pole drawn
/// from Fisher's distribution of concentration fisher_k about the set's pole (the angle by the
/// exact inversion of core/random.h fisherAngle, the azimuth uniform; a pole drawn below the
/// horizontal is the same plane's other normal and is reversed). The draws of plane k depend on
/// (seed, k) only, so a larger region gets more planes but the same ones where both have them.
struct JointSet {
  std::string name;
  double dip = 0.0;            // degrees, [0, 90]
  double dip_direction = 0.0;  // degrees, azimuth clockwise from north (+y)
  double spacing = 1.0;        // m, > 0
  double offset = 0.0;         // m, along the normal from origin
  Vec3 origin = Vec3::Zero();
  double spacing_jitter = 0.0;      // fraction of the spacing, [0, 1)
  double orientation_jitter = 0.0;  // degrees, [0, 90)
  double fisher_k = 0.0;            // Fisher's concentration K; 0: no Fisher scatter
  std::uint64_t seed = 0;
};

struct JointPlane {
  Plane plane;
  std::int64_t index = 0;  // k: plane 0 passes through origin + offset * normal
};

/// Most planes a rock mass may have (all sets and single planes together): more would take hours
/// to cut (a spacing in mm for m), and the blocks would exhaust the memory before saying so.
constexpr double kMaxRockPlanes = 2e4;

/// How many planes of `set` are expected across the convex hull of `points`: its extent along
/// the set's normal over the spacing (the mean gap, with or without jitter). Checks the set's
/// values (GeometryError naming the set); makes no plane.
double expectedPlaneCount(const JointSet& set, const std::vector<Vec3>& points);

/// Throws GeometryError if more than kMaxRockPlanes of the set's planes are expected across the
/// hull of `points`, naming the spacing, the count and the region's width.
void checkPlaneCount(const JointSet& set, const std::vector<Vec3>& points);

/// The planes of `set` that may meet the convex hull of `points` (the region's corners), ordered
/// by their index k along the normal (lowest first). Normals are the upward ones of normalFromDip
/// (jittered), so "above" a plane means the side its normal points to. Throws GeometryError,
/// with the numbers, for more than kMaxRockPlanes planes, before making them.
std::vector<JointPlane> jointSetPlanes(const JointSet& set, const std::vector<Vec3>& points);

}  // namespace polydem::geometry
