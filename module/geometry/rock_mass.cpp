// cutRockMass: the region's pieces split plane by plane (ConvexPolyhedron::split), with the sliver
// rule at every cut, the fixed and removed sides applied after each single plane, and the pieces
// of a non-convex region joined again wherever a block's two parts form a convex block.
#include "polydem/geometry/rock_mass.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>

#include "polydem/core/error.h"
#include "polydem/core/strings.h"

namespace polydem::geometry {

namespace {

// A block being cut.
struct Work {
  ConvexPolyhedron poly;
  std::vector<std::int8_t> sides;
  bool fixed = false;
};

struct Cut {
  Plane plane;
  std::string name;
  const SinglePlane* single = nullptr;  // null for a joint-set plane
};

std::optional<ConvexPolyhedron> tryBuild(const std::vector<Vec3>& points) {
  try {
    return ConvexPolyhedron::fromPoints(points);
  } catch (const GeometryError&) {
    return std::nullopt;  // too thin to be a polyhedron: a sliver of no volume
  }
}

// Whether the union of two blocks is convex, and if so the union.
std::optional<ConvexPolyhedron> convexUnion(const ConvexPolyhedron& a, const ConvexPolyhedron& b) {
  std::vector<Vec3> points = a.vertices();
  for (const Vec3& v : b.vertices()) {
    // A corner both have would be a duplicate point for the hull.
    const double tol = 1e-10 * std::max(a.lengthScale(), b.lengthScale());
    const bool shared = std::any_of(a.vertices().begin(), a.vertices().end(),
                                    [&](const Vec3& u) { return (u - v).norm() <= tol; });
    if (!shared) points.push_back(v);
  }
  std::optional<ConvexPolyhedron> hull = tryBuild(points);
  if (!hull) return std::nullopt;
  const double sum = a.volume() + b.volume();
  // The hull covers both; it is their union exactly when it holds no more volume than both.
  if (std::abs(hull->volume() - sum) > 1e-9 * hull->volume()) return std::nullopt;
  return hull;
}

// A description that would cut more blocks than this is a mistake (a spacing in mm for m), and
// would exhaust the memory before saying so.
constexpr std::size_t kMaxBlocks = 1'000'000;

class Cutter {
 public:
  explicit Cutter(const RockMassSpec& spec) : spec_(spec) {}

  RockMass run() {
    const std::vector<Cut> cuts = allCuts();
    for (const ConvexPolyhedron& piece : spec_.region.pieces) work_.push_back({piece, {}, false});
    report_.region_volume = spec_.region.volume;
    for (std::size_t c = 0; c < cuts.size(); ++c) apply(cuts[c], c);
    if (spec_.region.pieces.size() > 1) joinPieces();
    sweepSlivers();
    return result(cuts);
  }

 private:
  std::vector<Cut> allCuts() const {
    std::vector<Cut> cuts;
    for (const SinglePlane& p : spec_.planes) cuts.push_back({p.plane, p.name, &p});
    const std::vector<Vec3> corners = spec_.region.corners();
    for (const JointSet& set : spec_.joint_sets) {
      for (const JointPlane& jp : jointSetPlanes(set, corners)) {
        cuts.push_back({jp.plane, cat(set.name, "#", jp.index), nullptr});
      }
    }
    return cuts;
  }

  void apply(const Cut& cut, std::size_t index) {
    std::vector<Work> next;
    next.reserve(work_.size());
    bool cut_something = false;
    for (Work& w : work_) {
      if (!cut.single && w.fixed && !spec_.joints_cut_fixed) {
        w.sides.push_back(0);
        next.push_back(std::move(w));
        continue;
      }
      cut_something |= split(std::move(w), cut.plane, next);
    }
    work_ = std::move(next);
    if (work_.size() > kMaxBlocks) {
      throw GeometryError(cat("more than ", kMaxBlocks, " blocks after plane '", cut.name,
                              "': are the spacings right?"));
    }
    report_.planes += cut_something;
    if (cut.single) classify(*cut.single, index);
  }

  // Splits w by the plane into `out` (one or two blocks, or the sliver rule's answer); whether
  // it cut.
  bool split(Work w, const Plane& plane, std::vector<Work>& out) {
    const ConvexPolyhedron::Split parts = w.poly.split(plane);
    if (parts.below.empty() || parts.above.empty()) {
      w.sides.push_back(parts.below.empty() ? 1 : -1);
      out.push_back(std::move(w));
      return false;
    }
    std::optional<ConvexPolyhedron> below = tryBuild(parts.below);
    std::optional<ConvexPolyhedron> above = tryBuild(parts.above);
    const bool small_below = !below || isSliver(*below);
    const bool small_above = !above || isSliver(*above);
    if (!small_below && !small_above) {
      Work lo{std::move(*below), w.sides, w.fixed};
      lo.sides.push_back(-1);
      w.sides.push_back(1);
      w.poly = std::move(*above);
      out.push_back(std::move(lo));
      out.push_back(std::move(w));
      return true;
    }
    if (spec_.slivers == Slivers::kMerge || (small_below && small_above)) {
      ++report_.slivers_merged;
      w.sides.push_back(0);
      out.push_back(std::move(w));
      return false;
    }
    ++report_.slivers_dropped;
    const double whole = w.poly.volume();
    w.poly = small_below ? std::move(*above) : std::move(*below);
    report_.dropped_volume += whole - w.poly.volume();
    w.sides.push_back(small_below ? 1 : -1);
    out.push_back(std::move(w));
    return true;
  }

  bool isSliver(const ConvexPolyhedron& p) const {
    return p.volume() < spec_.min_volume || 2.0 * p.inradius() < spec_.min_thickness;
  }

  // The side of plane `index` a block is on; a block straddling it goes by its centroid.
  static Side sideOf(const Work& w, const Plane& plane, std::size_t index) {
    const std::int8_t s = w.sides[index];
    if (s != 0) return s > 0 ? Side::kAbove : Side::kBelow;
    return plane.signedDistance(w.poly.centroid()) > 0.0 ? Side::kAbove : Side::kBelow;
  }

  void classify(const SinglePlane& p, std::size_t index) {
    std::vector<Work> kept;
    for (Work& w : work_) {
      const Side side = sideOf(w, p.plane, index);
      if (p.remove != Side::kNone && side == p.remove) {
        ++report_.removed_blocks;
        report_.removed_volume += w.poly.volume();
        continue;
      }
      if (p.fixed != Side::kNone && side == p.fixed) w.fixed = true;
      kept.push_back(std::move(w));
    }
    work_ = std::move(kept);
  }

  // A profile's pieces are not joints: parts of one block (same side of every plane) in
  // neighbouring pieces are joined again wherever their union is convex.
  void joinPieces() {
    std::map<std::pair<std::vector<std::int8_t>, bool>, std::vector<std::size_t>> groups;
    for (std::size_t i = 0; i < work_.size(); ++i) {
      groups[{work_[i].sides, work_[i].fixed}].push_back(i);
    }
    std::vector<bool> gone(work_.size(), false);
    for (auto& [key, members] : groups) {
      for (bool joined = true; joined;) {
        joined = false;
        for (std::size_t a = 0; a < members.size() && !joined; ++a) {
          for (std::size_t b = a + 1; b < members.size() && !joined; ++b) {
            auto u = convexUnion(work_[members[a]].poly, work_[members[b]].poly);
            if (!u) continue;
            work_[members[a]].poly = std::move(*u);
            gone[members[b]] = true;
            members.erase(members.begin() + static_cast<std::ptrdiff_t>(b));
            joined = true;
          }
        }
      }
    }
    std::vector<Work> kept;
    for (std::size_t i = 0; i < work_.size(); ++i) {
      if (!gone[i]) kept.push_back(std::move(work_[i]));
    }
    work_ = std::move(kept);
  }

  // Blocks still slivers (parts of a profile's pieces that could not be joined): merged
  // into a neighbour where the union is convex, else dropped.
  void sweepSlivers() {
    for (std::size_t i = 0; i < work_.size();) {
      if (!isSliver(work_[i].poly)) {
        ++i;
        continue;
      }
      bool merged = false;
      for (std::size_t j = 0; j < work_.size() && spec_.slivers == Slivers::kMerge; ++j) {
        if (j == i || work_[j].fixed != work_[i].fixed) continue;
        if (auto u = convexUnion(work_[j].poly, work_[i].poly)) {
          work_[j].poly = std::move(*u);
          merged = true;
          break;
        }
      }
      if (merged) {
        ++report_.slivers_merged;
      } else {
        ++report_.slivers_dropped;
        report_.dropped_volume += work_[i].poly.volume();
      }
      work_.erase(work_.begin() + static_cast<std::ptrdiff_t>(i));
    }
  }

  RockMass result(const std::vector<Cut>& cuts) {
    RockMass mass;
    for (const Cut& c : cuts) {
      mass.planes.push_back(c.plane);
      mass.plane_names.push_back(c.name);
    }
    report_.smallest_volume = work_.empty() ? 0.0 : INFINITY;
    report_.smallest_thickness = report_.smallest_volume;
    for (Work& w : work_) {
      RockBlock b;
      b.vertices = w.poly.vertices();
      b.volume = w.poly.volume();
      b.centroid = w.poly.centroid();
      b.fixed = w.fixed;
      b.sides = std::move(w.sides);
      report_.smallest_volume = std::min(report_.smallest_volume, b.volume);
      report_.smallest_thickness = std::min(report_.smallest_thickness, 2.0 * w.poly.inradius());
      (b.fixed ? report_.fixed_blocks : report_.free_blocks) += 1;
      mass.blocks.push_back(std::move(b));
    }
    mass.report = report_;
    return mass;
  }

  const RockMassSpec& spec_;
  std::vector<Work> work_;
  RockMassReport report_;
};

}  // namespace

std::vector<Vec3> RockRegion::corners() const {
  std::vector<Vec3> out;
  for (const ConvexPolyhedron& p : pieces) {
    out.insert(out.end(), p.vertices().begin(), p.vertices().end());
  }
  return out;
}

RockMass cutRockMass(const RockMassSpec& spec) {
  if (spec.region.pieces.empty() || !(spec.region.volume > 0.0)) {
    throw GeometryError("the rock mass region has no volume");
  }
  if (!(spec.min_volume >= 0.0) || !std::isfinite(spec.min_volume)) {
    throw GeometryError("min_volume must be >= 0");
  }
  if (!(spec.min_thickness >= 0.0) || !std::isfinite(spec.min_thickness)) {
    throw GeometryError("min_thickness must be >= 0");
  }
  return Cutter(spec).run();
}

}  // namespace polydem::geometry
