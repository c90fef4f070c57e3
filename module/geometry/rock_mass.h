// Rock masses cut by joints (3DEC's jset and single-plane cuts): a region of rock, cut by joint
// sets and single planes (faults, a failure surface) into convex blocks; blocks on chosen sides
// of chosen planes become fixed or are removed; slivers are merged or dropped.
//
// Every plane is persistent: it cuts every block it crosses, except where cutting would leave a
// sliver, a piece smaller than `min_volume` or thinner than `min_thickness` (the joint then ends
// at that block, see RockMassSpec::slivers).
// The result depends only on the description: same blocks, same bits, on every machine and rank
// count (planes are applied in a fixed order, each split computed from the block's vertices).
//
// Non-persistent joints (ending inside the rock) are the next step, designed as in 3DEC: the
// joint plane is cut through as here, every face a block gets from a plane is tagged with the
// plane (RockBlock::sides), and the parts of the cut outside the joint's extent (a disc or a
// polygon in the plane) become rock bridges: the contacts across them are given the intact rock's
// strength (bonded until broken) instead of the joint's. See docs/scene-format.md.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "polydem/core/types.h"
#include "polydem/geometry/convex_polyhedron.h"
#include "polydem/geometry/joint_planes.h"

namespace polydem::geometry {

/// The rock before cutting: convex pieces that together fill it without overlap (one for a box or
/// a convex polyhedron; several for a non-convex slope profile).
struct RockRegion {
  std::vector<ConvexPolyhedron> pieces;
  double volume = 0.0;
  std::vector<Vec3> corners() const;  // every piece's vertices
};

/// An axis-aligned box (lo < hi).
RockRegion boxRegion(const Vec3& lo, const Vec3& hi);
/// The convex hull of `points`.
RockRegion polyhedronRegion(const std::vector<Vec3>& points);
/// A slope profile: the simple polygon `profile` of (x, z) points (convex or not, e.g. floor, toe,
/// face, crest, top) extruded across the slope from y = y_min to y = y_max.
RockRegion profileRegion(const std::vector<Vec2>& profile, double y_min, double y_max);

/// Which side of a plane: below is where the upward normal points away from (n . x < offset).
enum class Side : std::uint8_t { kNone, kBelow, kAbove };

/// One plane that cuts the whole mass: a fault, a failure surface, an excavation.
struct SinglePlane {
  std::string name;
  Plane plane;                // normal upward, as normalFromDip gives it
  Side fixed = Side::kNone;   // blocks on this side become fixed
  Side remove = Side::kNone;  // blocks on this side are removed
};

enum class Slivers : std::uint8_t {
  kMerge,  // a cut that would leave a sliver is not made in that block: the
           // sliver stays joined to the neighbour it would have been cut from
  kDrop,   // the sliver is cut off and dropped (its volume is reported)
};

/// How far a cut has got (RockMassSpec::progress).
struct CutProgress {
  std::size_t planes_done = 0, planes = 0;  // planes applied so far, of all
  std::size_t blocks = 0;                   // blocks so far
  double seconds = 0.0;                     // since the cut began
};

/// Most blocks a rock mass may be cut into unless its description raises the limit
/// (RockMassSpec::max_blocks; most planes: kMaxRockPlanes, joint_planes.h): beyond it a
/// description is likely a mistake (a spacing in mm for m) that would take hours and exhaust the
/// memory before saying so.
constexpr double kMaxRockBlocks = 1e6;

struct RockMassSpec {
  RockRegion region;
  std::vector<SinglePlane> planes;   // applied first, in order
  std::vector<JointSet> joint_sets;  // then each set's planes, set by set
  double min_volume = 0.0;           // m^3: smaller pieces are slivers
  double min_thickness = 0.0;        // m: so are pieces whose inscribed sphere is thinner (a thin
                                     // flake's small rotational inertia sets the time step)
  Slivers slivers = Slivers::kMerge;
  bool joints_cut_fixed = false;  // joint sets cut fixed blocks too (default: free only)
  /// Most blocks the cut may give (estimated before cutting, counted while cutting): a large
  /// mass is asked for explicitly (each block costs about 0.6 ms of cutting and some KB).
  double max_blocks = kMaxRockBlocks;
  /// Called every `progress_seconds` of a long cut (not at all if unset or the cut is quicker).
  std::function<void(const CutProgress&)> progress;
  double progress_seconds = 5.0;
};

/// A plane a block touches: `plane` indexes RockMass::planes; `side` is -1 where the block lies
/// below it, +1 above, 0 where the plane runs through the block uncut (a sliver merge).
struct PlaneSide {
  std::int32_t plane = 0;
  std::int8_t side = 0;
};

struct RockBlock {
  std::vector<Vec3> vertices;  // corners of the convex block
  double volume = 0.0;
  Vec3 centroid = Vec3::Zero();
  bool fixed = false;
  /// Only the planes that bound the block (a face of it lies on the plane: side -1 or +1) or
  /// run through it uncut (side 0), in the order applied: a few per block, however many planes
  /// cut the mass. The block lies wholly on one side of every other plane (sideOf tells which).
  std::vector<PlaneSide> sides;
};

/// The side of `plane` a block of these vertices is on: -1 below, +1 above, 0 across it (its
/// vertices on both sides, beyond a relative tolerance of the block's size).
std::int8_t sideOf(const std::vector<Vec3>& vertices, const Plane& plane);

/// A piece of rock named in a warning: where it is and how big.
struct RockPiece {
  Vec3 centroid = Vec3::Zero();
  double volume = 0.0;  // m^3
};

struct RockMassReport {
  double region_volume = 0.0;
  int planes = 0;  // planes that cut something
  int free_blocks = 0, fixed_blocks = 0;
  int removed_blocks = 0;  // on a `remove` side
  double removed_volume = 0.0;
  int slivers_merged = 0;   // cuts not made (kMerge), and parts of a profile's pieces merged
  int slivers_dropped = 0;  // pieces dropped (kDrop only)
  double dropped_volume = 0.0;
  std::vector<RockPiece> dropped;       // each piece dropped (kDrop)
  std::vector<RockPiece> kept_slivers;  // slivers no neighbour could take in convexly (kMerge):
                                        // kept as blocks of their own rather than leave a void
  double smallest_volume = 0.0;         // of the blocks kept
  double smallest_thickness = 0.0;  // diameter of the largest inscribed sphere, of the blocks kept
};

struct RockMass {
  std::vector<RockBlock> blocks;         // free and fixed, in the order the cutting produced them
  std::vector<Plane> planes;             // every plane applied, single planes first
  std::vector<std::string> plane_names;  // "fault-1", "J1#3" (set name, plane index k)
  RockMassReport report;
};

/// What a description would give, estimated from the region and the spacings before any cutting
/// (rock_mass_limits.cpp).
struct RockMassEstimate {
  struct Family {
    std::string name;      // a joint set's or a single plane's
    double spacing = 0.0;  // m (a single plane: the region's width along its normal)
    double planes = 0.0;   // expected planes across the region
  };
  std::vector<Family> families;
  double planes = 0.0;  // all families
  double blocks = 0.0;  // expected blocks
};
RockMassEstimate estimateRockMass(const RockMassSpec& spec);

/// Throws GeometryError, with the numbers and what to change, if the estimate exceeds
/// kMaxRockPlanes or spec.max_blocks. Allocates nothing in proportion to the planes or blocks.
void checkRockMassLimits(const RockMassSpec& spec);

/// Cuts the region. Throws GeometryError for an invalid description (a joint set's spacing, a
/// region without volume, one beyond the limits above: checked first); the message names the
/// set or plane. Throws Interrupted (core/interrupt.h) if a stop signal comes meanwhile.
RockMass cutRockMass(const RockMassSpec& spec);

}  // namespace polydem::geometry
