// The decomposition follows the work: blocks sized from where the free particles are
// (domain/block_fit.h), the block -> rank map balanced by the work of the last contact phase
// (sim/load_balance.h, domain/block_loads.h), a new decomposition adopted only when it is clearly
// better. None of it changes a result: pairs are evaluated in their canonical frame and summed in
// uid order whatever rank holds them (contact_phase.h).
//
// A LoadBalancer lives in the step's state (StepState::balancer): the "contacts" operator records
// each contact phase's work in it, the "balance" operator and Simulation::rebalance ask it for a
// better decomposition.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "polydem/domain/block_forest.h"
#include "polydem/domain/partition.h"
#include "polydem/sim/contact_record.h"
#include "polydem/sim/load_balance.h"

namespace polydem::sim {

struct StepState;

/// What the rebalancing did so far (the initial one at step 0 included).
struct BalanceLog {
  std::int64_t checks = 0;      // times the imbalance was looked at
  std::int64_t proposals = 0;   // times a new decomposition was computed
  std::int64_t adopted = 0;     // times it was installed
  double last_imbalance = 1.0;  // the work's imbalance at the last check (max / mean)
};

class LoadBalancer {
 public:
  /// The cost model of the scene's kernel (sim/load_balance.h).
  void setModel(const LoadModel& model) { model_ = model; }
  const LoadModel& model() const { return model_; }
  const BalanceLog& log() const { return log_; }
  /// The model's cost of this rank's last contact phase and particles.
  const StepWork& lastWork() const { return last_work_; }

  /// Samples the next contact phase per particle and pair, whatever the balance interval (the
  /// start's balance weighs the work at t = 0).
  void sampleNext() { sample_next_ = true; }
  /// Whether the contact phase of the step `next_step` is to be sampled for a balance check.
  bool samples(std::int64_t next_step, std::int64_t rebalance_every) const {
    return sample_next_ || (rebalance_every > 0 && next_step % rebalance_every == 0);
  }
  /// Records the work of the contact phase that produced `records` (before the storage changes:
  /// the records hold storage indices); `sample`: per particle and pair too, for the next check.
  void record(const particles::ParticleStorage& storage, const std::vector<PairWork>& work,
              bool sample);

  /// Weighs a new decomposition of s.forest against the current one by the last sampled contact
  /// phase and installs it if it is better by the margin; moves nothing (collective). Returns
  /// whether it was adopted.
  bool adopt(StepState& s);
  /// adopt(), and if adopted the particles and their histories moved to their new owners and
  /// the ghosts refreshed (collective, between steps).
  bool rebalance(StepState& s);

 private:
  LoadModel model_;
  BalanceLog log_;
  bool sample_next_ = false;
  LoadSample sample_;
  StepWork last_work_;
};

/// The scene's balancer as a partition method (METIS unless "sfc").
domain::PartitionMethod partitionMethod(const StepState& s);
/// The block -> rank map of s.forest for block weights `weights` (collective).
std::vector<int> rankMap(const StepState& s, std::span<const double> weights);
/// Block counts for `box` from the free particles' centroids; `collective`: each rank holds
/// some of them.
domain::Index3 fittedBlockCounts(const StepState& s, const domain::Aabb& box,
                                 const domain::Periodic& periodic, std::span<const Vec3> centroids,
                                 bool collective);

}  // namespace polydem::sim
