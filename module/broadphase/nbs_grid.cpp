#include "polydem/broadphase/nbs_grid.h"

#include <numeric>

#include "polydem/broadphase/grid_search.h"
#include "polydem/core/memory.h"

namespace polydem::broadphase {

NbsGrid::NbsGrid(const BroadPhaseParams& params) : params_(params) {
  detail::checkParams(params_);
}

void NbsGrid::findPairs(const SphereSet& spheres, double margin,
                        std::vector<CandidatePair>& out_pairs) {
  detail::PairWriter out(out_pairs);
  const detail::SceneBounds bounds = detail::checkAndBound(spheres, margin);
  all_.resize(spheres.centers.size());
  std::iota(all_.begin(), all_.end(), 0);
  grid_.build(spheres, all_, params_.cell_factor * (2.0 * bounds.max_radius + margin), bounds,
              false);
  detail::searchWithinSparse(grid_, margin, out);
  out.finish();
}

std::uint64_t NbsGrid::heapBytes() const {
  return capacityBytes(all_) + grid_.heapBytes();
}

}  // namespace polydem::broadphase
