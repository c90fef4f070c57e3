// Munjiza & Andrews' NBS search: one grid whose cells fit the largest sphere (edge = 2 * largest
// radius + margin), each cell checked against itself and its 13 forward neighbours. Linear in N
// for spheres of similar size; with sizes 10-100 apart the small spheres crowd the big cells and
// the cost grows with the square of that crowding, which is what "multilevel" removes.
#pragma once

#include "polydem/broadphase/broad_phase.h"
#include "polydem/broadphase/cell_grid.h"

namespace polydem::broadphase {

class NbsGrid final : public BroadPhase {
 public:
  /// Throws polydem::Error for parameters out of range (see BroadPhaseParams).
  explicit NbsGrid(const BroadPhaseParams& params = {});
  std::string_view name() const override { return "nbs"; }
  void findPairs(const SphereSet& spheres, double margin, std::vector<CandidatePair>& out) override;
  std::uint64_t heapBytes() const override;

 private:
  BroadPhaseParams params_;
  std::vector<std::int32_t> all_;
  detail::CellGrid grid_;
};

}  // namespace polydem::broadphase
