// The O(N^2) reference: every pair is tested. Used by the tests to check the grids.
#pragma once

#include "polydem/broadphase/broad_phase.h"

namespace polydem::broadphase {

class AllPairs final : public BroadPhase {
 public:
  std::string_view name() const override { return "all-pairs"; }
  void findPairs(const SphereSet& spheres, double margin, std::vector<CandidatePair>& out) override;
};

}  // namespace polydem::broadphase
