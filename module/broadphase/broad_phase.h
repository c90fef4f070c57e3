// The broad phase: from the bounding spheres of the local particles (owned, ghost copies and
// fixed boundary bodies) to the candidate pairs handed to the contact kernels, every step.
//
// Three methods share one interface and yield exactly the same set of pairs:
//   "multilevel"  Zhao et al. section 4: particles grouped by circumradius, one grid per group
//                 sized to it; linear in N for any mix of sizes (the default);
//   "nbs"         Munjiza & Andrews' no-binary-search grid, one cell size from the largest sphere;
//                 linear for spheres of similar size, slow when sizes differ;
//   "all-pairs"   O(N^2) reference for tests.
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "polydem/core/types.h"

namespace polydem::broadphase {

/// The local particles as parallel arrays, one entry per particle.
struct SphereSet {
  std::span<const Vec3> centers;
  std::span<const double> radii;         // circumradius about the centroid, >= 0
  std::span<const Uid> uids;             // global ids, unique within the set
  std::span<const std::uint8_t> active;  // 1 = owned by this rank; a pair needs >= 1 active
};

/// Local indices of a candidate pair, lower uid first: uids[i] < uids[j].
struct CandidatePair {
  std::int32_t i;
  std::int32_t j;
  friend bool operator==(const CandidatePair&, const CandidatePair&) = default;
};

struct BroadPhaseParams {
  /// multilevel: size ratio between consecutive levels (Zhao section 4: level k holds
  /// D/gamma^k < r <= D/gamma^(k-1)); must be > 1. 0 = automatic (cost-model grouping).
  double gamma = 0.0;
  /// multilevel: maximum number of levels; the last takes every smaller particle. 0 = automatic.
  int levels = 0;
  /// nbs and multilevel: cell edge = cell_factor * (2 * largest radius of the grid + margin).
  /// Must be >= 1; 1 is the smallest edge for which neighbour cells suffice (Munjiza & Andrews).
  double cell_factor = 1.0;
};

class BroadPhase {
 public:
  virtual ~BroadPhase() = default;
  virtual std::string_view name() const = 0;
  /// All pairs with |c_i - c_j| <= r_i + r_j + margin (withinReach() in overlap.h) and at least
  /// one active member, each once, lower uid first. Output order is unspecified (callers sort).
  /// `out` is cleared first. Throws polydem::Error for spans of different lengths, a negative or
  /// non-finite radius, a non-finite centre or margin, or more than 2^31 - 1 particles.
  virtual void findPairs(const SphereSet& spheres, double margin,
                         std::vector<CandidatePair>& out) = 0;
  /// Heap bytes its grids and scratch hold (capacities, core/memory.h).
  virtual std::uint64_t heapBytes() const { return 0; }
};

/// The method called `name` ("multilevel", "nbs", "all-pairs"). Throws polydem::Error listing
/// the known names for an unknown one, and for parameters out of range.
std::unique_ptr<BroadPhase> makeBroadPhase(std::string_view name,
                                           const BroadPhaseParams& params = {});
/// The names makeBroadPhase() accepts, default first.
std::vector<std::string> broadPhaseNames();

}  // namespace polydem::broadphase
