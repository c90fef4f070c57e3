// How the multi-level grid groups particles by size (internal, exposed for tests and benchmarks).
//
// Zhao section 4 groups the particles by circumradius with a fixed ratio gamma: with D the largest
// radius, group k holds D/gamma^k < r <= D/gamma^(k-1). A fixed gamma is a poor fit for real size
// distributions (a lone boundary block 1000x larger than the rest would leave many empty groups in
// between, and two sizes 10x apart need gamma just above 10, not 2), so by default the groups are
// chosen from the size distribution by a cost model:
//
//  * radii are binned by size, four bins per factor 2 (the same ratios Zhao's rule can express
//    with gamma = 2^(k/4)); a level is a run of consecutive bins, so it is Zhao's rule with a
//    ratio chosen per level;
//  * the plan minimises the expected number of sphere tests plus cell look-ups (each costed as
//    kLookupCost tests) over all runs of bins, by dynamic programming over the bins:
//      level with n members of largest radius d, cell edge l = 2d + margin, mean members per
//      cell o = n l^3 / V (V: the smaller of the centres' box and the spheres' packed volume);
//      pairs inside the level: 13.5 n o tests (own and 13 neighbour cells), 5 row look-ups per
//      occupied cell; for every smaller particle (largest radius r): the s^3 cells around it,
//      s = 1 + 2 (r + d + margin) / l (about 2 for r << d), each a look-up and o tests;
//      a level of at most kDirectMax members is searched directly: n^2/2 and n per smaller one;
//      each level also costs kLevelCost (building its grid);
//  * levels with no members never exist, so a lone huge boundary block becomes a level of one,
//    searched by one direct test per other particle, and never enlarges anyone else's cells.
//
// params.gamma > 0 applies Zhao's rule exactly; params.levels > 0 caps the number of levels
// (the last level takes all smaller particles). Only the speed depends on the plan: every plan
// yields the same pairs.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "polydem/broadphase/broad_phase.h"
#include "polydem/broadphase/scene_bounds.h"

namespace polydem::broadphase::detail {

inline constexpr int kMaxLevels = 16;
inline constexpr int kBinsPerOctave = 4;
inline constexpr int kBins = 24 * kBinsPerOctave;  // radii down to D / 2^24; smaller: last bin
inline constexpr std::int64_t kDirectMax = 8;
inline constexpr double kLookupCost = 4.0;
inline constexpr double kLevelCost = 256.0;

class LevelPlanner {
 public:
  /// Sets level_of[i] in [0, levels) for every sphere, 0 holding the largest spheres, every level
  /// non-empty, and returns the number of levels (0 for an empty set).
  int plan(const SphereSet& spheres, double margin, const SceneBounds& bounds,
           const BroadPhaseParams& params, std::vector<std::uint8_t>& level_of);

 private:
  int planZhao(const SphereSet& spheres, const BroadPhaseParams& params, double max_radius,
               std::vector<std::uint8_t>& level_of);
  int planByCost(const SphereSet& spheres, double margin, const SceneBounds& bounds,
                 const BroadPhaseParams& params, std::vector<std::uint8_t>& level_of);
  double levelCost(double n, double d, double below_r, double below_n, double margin, double volume,
                   double cell_factor) const;

  std::array<std::int64_t, kBins> count_{};
  std::array<double, kBins> max_r_{};
  std::array<std::uint8_t, kBins> level_of_bin_{};
  std::array<std::array<double, kBins + 1>, kMaxLevels + 1> best_{};
  std::array<std::array<int, kBins + 1>, kMaxLevels + 1> from_{};
};

/// Bin of a radius r <= max_radius: floor(kBinsPerOctave * log2(max_radius / r)), clamped.
int radiusBin(double r, double max_radius);

}  // namespace polydem::broadphase::detail
