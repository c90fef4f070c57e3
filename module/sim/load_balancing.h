// The decomposition follows the work: blocks sized from where the free particles are
// (domain/block_fit.h), the block -> rank map balanced by the work of the last contact phase
// (sim/load_balance.h, domain/block_loads.h), a new decomposition adopted only when it is clearly
// better. None of it changes a result: pairs are evaluated in their canonical frame and summed in
// uid order whatever rank holds them (contact_phase.h). Functions of the step's state
// (step/step_state.h); the step's "balance" operator and Simulation::rebalance call them.
#pragma once

#include <span>
#include <vector>

#include "polydem/domain/block_forest.h"
#include "polydem/domain/partition.h"
#include "polydem/sim/step/step_state.h"

namespace polydem::sim {

/// The scene's balancer as a partition method (METIS unless "sfc").
domain::PartitionMethod partitionMethod(const StepState& s);
/// The block -> rank map of s.forest for block weights `weights` (collective).
std::vector<int> rankMap(const StepState& s, std::span<const double> weights);
/// Block counts for `box` from the free particles' centroids; `collective`: each rank holds
/// some of them.
domain::Index3 fittedBlockCounts(const StepState& s, const domain::Aabb& box,
                                 const domain::Periodic& periodic, std::span<const Vec3> centroids,
                                 bool collective);
/// Weighs a new decomposition against the current one by the work of the last sampled contact
/// phase and installs it if it is better by the margin; moves nothing (collective). Returns
/// whether it was adopted.
bool balanceDecomposition(StepState& s);

}  // namespace polydem::sim
