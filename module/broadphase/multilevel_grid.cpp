#include "polydem/broadphase/multilevel_grid.h"

#include <algorithm>

#include "polydem/core/memory.h"

namespace polydem::broadphase {

MultiLevelGrid::MultiLevelGrid(const BroadPhaseParams& params) : params_(params) {
  detail::checkParams(params_);
}

void MultiLevelGrid::findPairs(const SphereSet& spheres, double margin,
                               std::vector<CandidatePair>& out_pairs) {
  detail::PairWriter out(out_pairs);
  const detail::SceneBounds bounds = detail::checkAndBound(spheres, margin);
  const int levels = planner_.plan(spheres, margin, bounds, params_, level_of_);

  // Members of each level, by counting sort on the level (stable: input order within a level).
  info_.assign(levels, LevelInfo{0, 0.0, bounds.max_radius});
  for (std::size_t i = 0; i < level_of_.size(); ++i) {
    LevelInfo& info = info_[level_of_[i]];
    ++info.count;
    info.max_radius = std::max(info.max_radius, spheres.radii[i]);
    info.min_radius = std::min(info.min_radius, spheres.radii[i]);
  }
  level_start_.assign(levels + 1, 0);
  for (int k = 0; k < levels; ++k) level_start_[k + 1] = level_start_[k] + info_[k].count;
  members_.resize(level_of_.size());
  for (std::size_t i = 0; i < level_of_.size(); ++i) {
    members_[level_start_[level_of_[i]]++] = static_cast<std::int32_t>(i);
  }
  for (int k = levels; k > 0; --k) level_start_[k] = level_start_[k - 1];
  level_start_[0] = 0;

  if (grids_.size() < static_cast<std::size_t>(levels)) grids_.resize(levels);
  for (int k = 0; k < levels; ++k) {
    const std::span<const std::int32_t> members(members_.data() + level_start_[k],
                                                static_cast<std::size_t>(info_[k].count));
    const bool searched_by_smaller = k + 1 < levels && info_[k].count > detail::kDirectMax;
    grids_[k].build(spheres, members, params_.cell_factor * (2.0 * info_[k].max_radius + margin),
                    bounds, searched_by_smaller);
  }
  for (int k = 0; k < levels; ++k) {
    const bool direct = info_[k].count <= detail::kDirectMax;
    if (direct) {
      detail::searchWithinDirect(grids_[k], margin, out);
    } else {
      detail::searchWithin(grids_[k], margin, out);
    }
    // Zhao step k: every smaller group searched in group k's cells.
    for (int j = k + 1; j < levels; ++j) {
      if (direct) {
        detail::searchAcrossDirect(grids_[k], grids_[j], margin, out);
      } else {
        detail::searchAcross(grids_[k], grids_[j], margin, out, across_);
      }
    }
  }
  out.finish();
}

std::uint64_t MultiLevelGrid::heapBytes() const {
  std::uint64_t bytes = capacityBytes(level_of_) + capacityBytes(level_start_) +
                        capacityBytes(members_) + capacityBytes(grids_) + capacityBytes(info_) +
                        capacityBytes(across_.found) + capacityBytes(across_.survivors);
  for (const auto& grid : grids_) bytes += grid.heapBytes();
  return bytes;
}

}  // namespace polydem::broadphase
