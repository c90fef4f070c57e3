// A run's state to and from its saved state (saved_state.h; checkpoint/checkpoint.h stores it):
// captured between two steps, and restored on any number of ranks so that stepping on gives the
// same bits as a run that never stopped.
//
// What a step reads besides the scene: particle poses and leapfrog velocities (stored as they
// are, at t - dt/2, so the leapfrog is not restarted), the pair histories (shear force, normal,
// kernel warm start), step and exact time of the current stage's loop, and the stage itself.
// Everything else (derived particle data, candidate pairs, ghosts, forces) is recomputed from
// these at the start of the next step, and is the same on any rank count (contact_phase.h).
#pragma once

#include <string>

#include "polydem/comm/history_routing.h"
#include "polydem/sim/history_chunks.h"
#include "polydem/sim/saved_state.h"
#include "polydem/sim/stages.h"
#include "polydem/sim/step/step_state.h"

namespace polydem::sim {

class Restart {
 public:
  /// This rank's part of a checkpoint of `s` between steps (not collective): replicated tables,
  /// this rank's free particles (and the fixed/driven ones on rank 0); no pair history (below).
  /// `scene_toml`, `scene_file` and `run_state` are stored as given.
  static CheckpointData capture(const StepState& s, const Stages& stages,
                                const std::string& scene_toml, const std::string& scene_file,
                                const std::string& run_state);
  /// The pair histories this rank writes, each pair once over all ranks, without a copy: indices
  /// into the history table (valid until the next step).
  static HistoryView historyView(const StepState& s);
  /// The same pair histories copied into `d`'s four history tables.
  static void copyHistories(const StepState& s, CheckpointData& d);

  /// Restores `checkpoint` (what checkpoint::readCheckpoint returned on this rank, read from
  /// `file`, named in every error) into `s`, in the order the simulation builds: the calls below
  /// in turn. Throws CheckpointError for a file that does not fit the scene.
  Restart(StepState& s, const CheckpointData& checkpoint, const std::string& file)
      : s_(s), c_(checkpoint), file_(file) {}
  /// After the shape and material tables are built: the shapes (with their faces' joint planes),
  /// materials and time step must be the stored ones.
  void checkTables() const;
  /// After the bolts are built: their stored state.
  void restoreBolts() const;
  /// After the extents are known: the decomposition, every particle to its owner and every pair
  /// history of `histories` to the owners of its particles, chunk by chunk, each merged into the
  /// table in place (collective). Returns how the histories were routed.
  comm::HistoryRoutingStats restoreParticles(HistoryChunks& histories) const;
  /// After the step is registered: the stage, step and exact time, and fresh ghosts.
  void restoreStage(Stages& stages) const;

 private:
  domain::Index3 blockCounts(const domain::Aabb& box, bool same_ranks) const;
  void addParticles() const;

  StepState& s_;
  const CheckpointData& c_;
  const std::string& file_;
};

}  // namespace polydem::sim
