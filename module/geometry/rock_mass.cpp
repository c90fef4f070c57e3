// cutRockMass: the region's pieces split plane by plane (ConvexPolyhedron::split), with the sliver
// rule at every cut, the fixed and removed sides applied after each single plane, and the pieces
// of a non-convex region joined again wherever a block's two parts form a convex block.
#include "polydem/geometry/rock_mass.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <optional>

#include "polydem/core/error.h"
#include "polydem/core/interrupt.h"
#include "polydem/core/random.h"
#include "polydem/core/strings.h"
#include "polydem/core/tolerance.h"
#include "polydem/geometry/polyhedron_split.h"

namespace polydem::geometry {

namespace {

// A block being cut. `key` digests the block's side of every plane applied so far (-1, 0, +1, in
// order): parts of one block in neighbouring pieces of a profile have the same key. `last` is
// its side of the plane just applied. `sides` keeps only the planes it touches (RockBlock).
struct Work {
  ConvexPolyhedron poly;
  std::vector<PlaneSide> sides;
  bool fixed = false;
  std::uint64_t key = 0;
  std::int8_t last = 0;
};

// Records w's side of the plane being applied.
void note(Work& w, std::int8_t side) {
  w.key = splitMix64(w.key ^ static_cast<std::uint64_t>(side + 2));
  w.last = side;
}

// Vertices of p within the plane tolerance of `plane`.
int onPlane(const ConvexPolyhedron& p, const Plane& plane) {
  const double tol = absTol(p.lengthScale(), RelTol::kPlane);
  int n = 0;
  for (const Vec3& v : p.vertices()) n += std::abs(plane.signedDistance(v)) <= tol;
  return n;
}

// Whether p still touches the plane as `s` says: a face on it (three vertices), or across it.
// A later cut may have taken the face away: the plane then no longer bounds the block.
bool touches(const ConvexPolyhedron& p, const Plane& plane, const PlaneSide& s) {
  if (s.side == 0) return sideOf(p.vertices(), plane) == 0;
  return onPlane(p, plane) >= 3;
}

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

// Blocks cut (or not) by a plane between two looks at the stop flag and the clock.
constexpr std::size_t kPollEvery = 256;

// The cut is depth first: each piece of the region goes through the planes in order, and each
// part a plane makes goes on through the rest before its neighbour does. The blocks come out in
// the order a plane-by-plane cut of the whole mass gives (parts below before parts above), with
// the same bits (each split depends on its block alone), but only the blocks on the way down are
// held, and no list of every block is moved once per plane.
class Cutter {
 public:
  explicit Cutter(const RockMassSpec& spec)
      : spec_(spec), start_(std::chrono::steady_clock::now()), last_progress_(start_) {}

  RockMass run() {
    cuts_ = allCuts();
    if (static_cast<double>(cuts_.size()) > kMaxRockPlanes) {
      throw GeometryError(cat(cuts_.size(), " planes cross the region, more than the limit of ",
                              num(kMaxRockPlanes), ": increase the joint sets' spacings"));
    }
    cut_any_.assign(cuts_.size(), false);
    report_.region_volume = spec_.region.volume;
    for (const ConvexPolyhedron& piece : spec_.region.pieces) descend({piece, {}, false});
    tallyInCutOrder();
    if (spec_.region.pieces.size() > 1) joinPieces();
    sweepSlivers();
    RockMass mass = result();
    checkVolumes(mass);
    return mass;
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

  // A block and the next plane it meets.
  struct Pending {
    Work w;
    std::size_t cut = 0;
  };

  // Takes `piece` through every plane; its blocks join work_ in order.
  void descend(Work piece) {
    std::vector<Pending> stack;
    stack.push_back({std::move(piece), 0});
    std::vector<Work> parts;
    while (!stack.empty()) {
      Pending p = std::move(stack.back());
      stack.pop_back();
      for (; p.cut < cuts_.size(); ++p.cut) {
        furthest_ = std::max(furthest_, p.cut);
        if (++ticks_ % kPollEvery == 0) poll(furthest_, work_.size() + stack.size() + 1);
        parts.clear();
        if (!apply(cuts_[p.cut], p.cut, std::move(p.w), parts)) break;  // removed
        if (parts.size() == 1) {
          p.w = std::move(parts[0]);
          continue;
        }
        // Two parts: the one above waits while the one below goes on.
        stack.push_back({std::move(parts[1]), p.cut + 1});
        p.w = std::move(parts[0]);
      }
      if (p.cut < cuts_.size()) continue;
      work_.push_back(std::move(p.w));
      // The estimate (checkRockMassLimits) came first; this guards against its being far off.
      if (static_cast<double>(work_.size() + stack.size()) > spec_.max_blocks) {
        throw GeometryError(cat("more than ", num(spec_.max_blocks),
                                " blocks (max_blocks): increase the joint sets' spacings"));
      }
    }
  }

  // Cut `index` applied to w: its parts (one or two) into `out`; false if w is removed.
  bool apply(const Cut& cut, std::size_t index, Work w, std::vector<Work>& out) {
    if (!cut.single && w.fixed && !spec_.joints_cut_fixed) {
      note(w, 0);  // not cut by the joint: fixed rock stays whole
      out.push_back(std::move(w));
      return true;
    }
    if (split(std::move(w), cut.plane, static_cast<std::int32_t>(index), out)) {
      cut_any_[index] = true;
    }
    if (!cut.single) return true;
    return classify(*cut.single, index, out);
  }

  // The removed and dropped pieces, counted in the order of a plane-by-plane cut: by plane, and
  // along a plane in block order, which is the order the depth-first cut met them in.
  void tallyInCutOrder() {
    const auto by_cut = [](const auto& a, const auto& b) { return a.first < b.first; };
    std::stable_sort(removed_.begin(), removed_.end(), by_cut);
    std::stable_sort(dropped_.begin(), dropped_.end(), by_cut);
    for (const auto& [cut, volume] : removed_) {
      ++report_.removed_blocks;
      report_.removed_volume += volume;
    }
    for (const auto& [cut, piece] : dropped_) drop(piece);
    for (const bool cut : cut_any_) report_.planes += cut;
  }

  // Every kPollEvery blocks offered to a plane: a stop signal ends the cut; a progress line
  // every few seconds. The cut goes depth first: `plane` is the furthest plane reached so far.
  void poll(std::size_t plane, std::size_t blocks) {
    throwIfInterrupted([&] {
      return cat("cutting the rock mass (plane ", plane + 1, " of ", cuts_.size(), ", ", blocks,
                 " blocks so far)");
    });
    if (!spec_.progress) return;
    const auto now = std::chrono::steady_clock::now();
    if (std::chrono::duration<double>(now - last_progress_).count() < spec_.progress_seconds) {
      return;
    }
    last_progress_ = now;
    spec_.progress(
        {plane, cuts_.size(), blocks, std::chrono::duration<double>(now - start_).count()});
  }

  // Splits w by the plane into `out` (one or two blocks, or the sliver rule's answer); whether
  // it cut.
  bool split(Work w, const Plane& plane, std::int32_t index, std::vector<Work>& out) {
    // Most planes miss most blocks: that is decided without making the parts.
    if (const int side = splitSide(w.poly, plane); side != 0) {
      note(w, static_cast<std::int8_t>(side));
      out.push_back(std::move(w));
      return false;
    }
    const ConvexPolyhedron::Split parts = w.poly.split(plane);
    std::optional<ConvexPolyhedron> below = tryBuild(parts.below);
    std::optional<ConvexPolyhedron> above = tryBuild(parts.above);
    const bool small_below = !below || isSliver(*below);
    const bool small_above = !above || isSliver(*above);
    if (!small_below && !small_above) {
      Work lo{std::move(*below), w.sides, w.fixed, w.key, 0};
      w.poly = std::move(*above);
      out.push_back(cutPart(std::move(lo), index, -1));
      out.push_back(cutPart(std::move(w), index, 1));
      return true;
    }
    if (spec_.slivers == Slivers::kMerge || (small_below && small_above)) {
      ++report_.slivers_merged;
      note(w, 0);
      w.sides.push_back({index, 0});  // the joint ends at this block
      out.push_back(std::move(w));
      return false;
    }
    const double whole = w.poly.volume();
    const std::optional<ConvexPolyhedron>& small = small_below ? below : above;
    const std::vector<Vec3>& small_points = small_below ? parts.below : parts.above;
    w.poly = small_below ? std::move(*above) : std::move(*below);
    dropped_.push_back({static_cast<std::size_t>(index),
                        {small ? small->centroid() : mean(small_points), whole - w.poly.volume()}});
    out.push_back(cutPart(std::move(w), index, small_below ? 1 : -1));
    return true;
  }

  // A part of a cut block: the new face on plane `index`; planes whose face the cut took off
  // are forgotten.
  Work cutPart(Work w, std::int32_t index, std::int8_t side) {
    note(w, side);
    w.sides.push_back({index, side});
    forgetUntouched(w);
    return w;
  }

  void forgetUntouched(Work& w) const {
    std::erase_if(w.sides, [&](const PlaneSide& s) {
      return !touches(w.poly, cuts_[static_cast<std::size_t>(s.plane)].plane, s);
    });
  }

  static Vec3 mean(const std::vector<Vec3>& points) {
    Vec3 sum = Vec3::Zero();
    for (const Vec3& p : points) sum += p;
    return points.empty() ? sum : Vec3(sum / static_cast<double>(points.size()));
  }

  void drop(const RockPiece& piece) {
    ++report_.slivers_dropped;
    report_.dropped_volume += piece.volume;
    report_.dropped.push_back(piece);
  }

  bool isSliver(const ConvexPolyhedron& p) const {
    return p.volume() < spec_.min_volume || 2.0 * p.inradius() < spec_.min_thickness;
  }

  // The side of the plane just applied a block is on; a block straddling it goes by its
  // centroid.
  static Side sideOfLast(const Work& w, const Plane& plane) {
    if (w.last != 0) return w.last > 0 ? Side::kAbove : Side::kBelow;
    return plane.signedDistance(w.poly.centroid()) > 0.0 ? Side::kAbove : Side::kBelow;
  }

  // The parts in `parts` that plane p removes are noted and taken out; those it fixes, fixed.
  // False if none is left.
  bool classify(const SinglePlane& p, std::size_t index, std::vector<Work>& parts) {
    std::erase_if(parts, [&](Work& w) {
      const Side side = sideOfLast(w, p.plane);
      if (p.remove != Side::kNone && side == p.remove) {
        removed_.push_back({index, w.poly.volume()});
        return true;
      }
      if (p.fixed != Side::kNone && side == p.fixed) w.fixed = true;
      return false;
    });
    return !parts.empty();
  }

  // A profile's pieces are not joints: parts of one block (same side of every plane) in
  // neighbouring pieces are joined again wherever their union is convex.
  // (Parts with the same key are on the same side of every plane: a 64-bit digest of the sides,
  // whose collisions would only offer a pair to the convexity test below.)
  void joinPieces() {
    std::map<std::pair<std::uint64_t, bool>, std::vector<std::size_t>> groups;
    for (std::size_t i = 0; i < work_.size(); ++i) {
      groups[{work_[i].key, work_[i].fixed}].push_back(i);
    }
    std::vector<bool> gone(work_.size(), false);
    for (auto& [key, members] : groups) {
      for (bool joined = true; joined;) {
        joined = false;
        for (std::size_t a = 0; a < members.size() && !joined; ++a) {
          for (std::size_t b = a + 1; b < members.size() && !joined; ++b) {
            auto u = convexUnion(work_[members[a]].poly, work_[members[b]].poly);
            if (!u) continue;
            absorb(work_[members[a]], std::move(*u), work_[members[b]]);
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

  // `into` becomes `hull`, the convex union of itself and `other`, and touches the planes
  // either touched that its new faces still lie on.
  void absorb(Work& into, ConvexPolyhedron hull, const Work& other) const {
    into.poly = std::move(hull);
    for (const PlaneSide& s : other.sides) {
      const bool known = std::any_of(into.sides.begin(), into.sides.end(),
                                     [&](const PlaneSide& t) { return t.plane == s.plane; });
      if (!known) into.sides.push_back(s);
    }
    std::sort(into.sides.begin(), into.sides.end(),
              [](const PlaneSide& a, const PlaneSide& b) { return a.plane < b.plane; });
    forgetUntouched(into);
  }

  // Blocks still slivers (parts of a profile's pieces that could not be joined). kMerge: merged
  // into a neighbour where the union is convex (they share a face), else kept as a block of its
  // own, never dropped: that would leave a void in the rock. kDrop: dropped.
  void sweepSlivers() {
    for (std::size_t i = 0; i < work_.size();) {
      if (!isSliver(work_[i].poly)) {
        ++i;
        continue;
      }
      if (spec_.slivers == Slivers::kDrop) {
        drop({work_[i].poly.centroid(), work_[i].poly.volume()});
        work_.erase(work_.begin() + static_cast<std::ptrdiff_t>(i));
        continue;
      }
      bool merged = false;
      for (std::size_t j = 0; j < work_.size(); ++j) {
        if (j == i || work_[j].fixed != work_[i].fixed) continue;
        if (auto u = convexUnion(work_[j].poly, work_[i].poly)) {
          absorb(work_[j], std::move(*u), work_[i]);
          merged = true;
          break;
        }
      }
      if (!merged) {
        report_.kept_slivers.push_back({work_[i].poly.centroid(), work_[i].poly.volume()});
        ++i;
        continue;
      }
      ++report_.slivers_merged;
      work_.erase(work_.begin() + static_cast<std::ptrdiff_t>(i));
    }
  }

  // Nothing is lost: the blocks kept, removed and dropped fill the region (each split and join
  // conserves volume up to round-off; convexUnion accepts 1e-9 of a block).
  void checkVolumes(const RockMass& mass) const {
    double kept = 0.0;
    for (const RockBlock& b : mass.blocks) kept += b.volume;
    const double sum = kept + report_.removed_volume + report_.dropped_volume;
    const double region = report_.region_volume;
    if (std::abs(sum - region) > 1e-6 * region) {
      throw GeometryError(cat("the blocks (", num(kept), " m^3), removed (",
                              num(report_.removed_volume), " m^3) and dropped pieces (",
                              num(report_.dropped_volume), " m^3) add up to ", num(sum),
                              " m^3, not the region's ", num(region),
                              " m^3: please report this as a bug, with the scene"));
    }
  }

  RockMass result() {
    RockMass mass;
    mass.blocks.reserve(work_.size());
    for (const Cut& c : cuts_) {
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
      w.poly = ConvexPolyhedron();  // its block holds what is kept: the two never both whole
    }
    work_ = std::vector<Work>();
    mass.report = report_;
    return mass;
  }

  const RockMassSpec& spec_;
  std::vector<Cut> cuts_;
  std::vector<Work> work_;
  RockMassReport report_;
  std::vector<bool> cut_any_;                               // per plane: whether it cut a block
  std::vector<std::pair<std::size_t, double>> removed_;     // (plane, volume), as met
  std::vector<std::pair<std::size_t, RockPiece>> dropped_;  // (plane, piece), as met
  std::chrono::steady_clock::time_point start_, last_progress_;
  std::size_t ticks_ = 0;     // blocks offered to planes so far
  std::size_t furthest_ = 0;  // the furthest plane a block has been offered to
};

}  // namespace

std::vector<Vec3> RockRegion::corners() const {
  std::vector<Vec3> out;
  for (const ConvexPolyhedron& p : pieces) {
    out.insert(out.end(), p.vertices().begin(), p.vertices().end());
  }
  return out;
}

std::int8_t sideOf(const std::vector<Vec3>& vertices, const Plane& plane) {
  Vec3 lo = Vec3::Constant(INFINITY), hi = Vec3::Constant(-INFINITY);
  for (const Vec3& v : vertices) lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
  const double tol = vertices.empty() ? 0.0 : absTol((hi - lo).norm(), RelTol::kPlane);
  bool below = false, above = false;
  for (const Vec3& v : vertices) {
    const double s = plane.signedDistance(v);
    below |= s < -tol;
    above |= s > tol;
  }
  return below && above ? 0 : (above ? 1 : -1);
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
  checkRockMassLimits(spec);
  return Cutter(spec).run();
}

}  // namespace polydem::geometry
