// Zhao et al. section 4: the non-uniform (multi-level) contact search. Particles are grouped by
// circumradius (level_plan.h); each group gets its own grid with cells sized to the group's
// largest member; group k is searched against itself (NBS cells, Zhao step k "with the method in
// step 1") and then against every smaller group by mapping the smaller particles into group k's
// cells (Zhao step k: "contact detection is performed between the elements of group k and the
// remaining group elements"). Every pair is found once, in the grid of its larger member.
//
// Cost: each particle is tested against the members of its own group near it and, for each larger
// group k, against the members of group k that can reach the box of its own cell (found in the
// 2 x 2 x 2 or so cells of group k's size around that cell, then culled by one box test per cell
// of small particles); neither depends on how many particles there are, so the search is linear
// in N for any size mix.
//
// Buffers (grids, member lists, the level plan) are kept between calls: once warm, a call with a
// similar scene allocates nothing except when `out` must grow.
#pragma once

#include <vector>

#include "polydem/broadphase/broad_phase.h"
#include "polydem/broadphase/cell_grid.h"
#include "polydem/broadphase/grid_search.h"
#include "polydem/broadphase/level_plan.h"

namespace polydem::broadphase {

/// One level of the last search, for reports and tests.
struct LevelInfo {
  std::int32_t count = 0;
  double max_radius = 0.0;
  double min_radius = 0.0;
};

class MultiLevelGrid final : public BroadPhase {
 public:
  /// Throws polydem::Error for parameters out of range (see BroadPhaseParams).
  explicit MultiLevelGrid(const BroadPhaseParams& params = {});
  std::string_view name() const override { return "multilevel"; }
  void findPairs(const SphereSet& spheres, double margin, std::vector<CandidatePair>& out) override;
  /// The levels of the last findPairs(), largest spheres first.
  const std::vector<LevelInfo>& levels() const { return info_; }
  std::uint64_t heapBytes() const override;

 private:
  BroadPhaseParams params_;
  detail::LevelPlanner planner_;
  std::vector<std::uint8_t> level_of_;
  std::vector<std::int32_t> level_start_;
  std::vector<std::int32_t> members_;
  std::vector<detail::CellGrid> grids_;
  detail::AcrossScratch across_;
  std::vector<LevelInfo> info_;
};

}  // namespace polydem::broadphase
