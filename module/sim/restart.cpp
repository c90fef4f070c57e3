// A Simulation to and from its saved state (saved_state.h; checkpoint/checkpoint.h stores it):
// capture between two steps, and a restore on any number of ranks that continues with the same bits
// as a run that never stopped.
//
// What a step reads besides the scene: particle poses and leapfrog velocities (stored as they
// are, at t - dt/2, so the leapfrog is not restarted), the pair histories (shear force, normal,
// kernel warm start), step and exact time of the current stage's loop, and the stage itself.
// Everything else (derived particle data, candidate pairs, ghosts, forces) is recomputed from
// these at the start of the next step, and is the same on any rank count (contact_phase.h).
#include <algorithm>
#include <limits>
#include <memory>

#include "polydem/comm/history_routing.h"
#include "polydem/core/error.h"
#include "polydem/core/logging.h"
#include "polydem/core/mpi_env.h"
#include "polydem/core/strings.h"
#include "polydem/domain/rebalance.h"
#include "polydem/sim/history_chunks.h"
#include "polydem/sim/load_balancing.h"
#include "polydem/sim/simulation.h"
#include "polydem/sim/step/operators.h"

namespace polydem::sim {

namespace {

// The rank that writes a pair history: every evaluated pair has a free member, and the history
// follows each free member to its owner, so the owner of the lower-uid free member holds it (other
// ranks may hold stale copies from before a migration; they are left out).
bool writesPair(const particles::ParticleStorage& storage, const particles::PairKey& key,
                int rank) {
  for (Uid uid : {key.lo, key.hi}) {
    const int i = storage.indexOf(uid);
    if (i >= 0 && static_cast<std::size_t>(i) < storage.localCount()) {
      if (storage[i].isFree()) return true;
      continue;  // replicated: the other member decides
    }
    // Not held here as a local particle: a free particle owned elsewhere, or an unknown one.
    if (i < 0 || !storage[i].isGlobal()) return false;
  }
  return rank == 0;  // both replicated (never evaluated, but kept once if present)
}

}  // namespace

// Everything but the pair histories.
CheckpointData Simulation::capture(const std::string& scene_toml, const std::string& scene_file,
                                   const std::string& run_state) const {
  requireBetweenSteps("checkpoint");
  CheckpointData d;
  d.scene_toml = scene_toml;
  d.scene_file = scene_file;
  d.step = state_.loop.step();
  d.time_digits = state_.loop.exactTime().digits();
  d.time = state_.loop.time();
  d.dt = dt();
  d.stage =
      state_.stage == Stage::kEquilibrium ? CheckpointStage::kEquilibrium : CheckpointStage::kMain;
  d.equilibrium_steps =
      state_.stage == Stage::kEquilibrium ? state_.loop.step() : equilibrium_steps_;
  d.equilibrium_reached = equilibrium_reached_;
  d.shapes = shapeRecords(state_.shapes);
  d.materials = state_.scene.materials;
  d.interactions = state_.scene.interactions;
  d.domain.lo = state_.forest->domain().lo;
  d.domain.hi = state_.forest->domain().hi;
  d.domain.blocks = state_.forest->counts();
  d.domain.periodic = state_.forest->periodic();
  d.domain.rank_map = state_.forest->rankMap();
  d.domain.ranks = state_.ranks;
  d.run_state = run_state;
  d.bolt_states = state_.bolts.states();
  for (std::size_t i = 0; i < state_.storage.localCount(); ++i) {
    const auto& p = state_.storage[i];
    if (p.isGlobal() && state_.rank != 0) continue;  // replicated: rank 0's copy only
    d.particles.push_back(p);
  }
  return d;
}

CheckpointData Simulation::checkpoint(const std::string& scene_toml, const std::string& scene_file,
                                      const std::string& run_state) const {
  CheckpointData d = capture(scene_toml, scene_file, run_state);
  particles::HistoryRecords records;
  const HistoryView view = historyView();
  for (std::uint32_t k : view.pairs) state_.history.copyPair(k, records);
  d.pair_keys = std::move(records.keys);
  d.pair_histories = std::move(records.entries);
  d.sub_keys = std::move(records.sub_keys);
  d.sub_histories = std::move(records.sub_entries);
  return d;
}

CheckpointData Simulation::checkpointForWriting(const std::string& scene_toml,
                                                const std::string& scene_file,
                                                const std::string& run_state) const {
  CheckpointData d = capture(scene_toml, scene_file, run_state);
  d.history_view = historyView();
  return d;
}

HistoryView Simulation::historyView() const {
  HistoryView view;
  view.table = &state_.history;
  const auto keys = state_.history.keys();
  if (keys.size() > std::numeric_limits<std::uint32_t>::max()) {
    throw Error(cat("checkpoint: ", keys.size(), " pair histories on rank ", state_.rank,
                    ", more than a checkpoint's index of them counts"));
  }
  for (std::size_t k = 0; k < keys.size(); ++k) {
    if (writesPair(state_.storage, keys[k], state_.rank)) {
      view.pairs.push_back(static_cast<std::uint32_t>(k));
    }
  }
  return view;
}

Simulation::Simulation(const setup::Setup& scene, const CheckpointData& checkpoint,
                       const std::string& file, MPI_Comm comm)
    : Simulation(scene, checkpoint, *std::make_unique<SavedHistoryChunks>(checkpoint, comm), file,
                 comm) {}

Simulation::Simulation(const setup::Setup& scene, const CheckpointData& checkpoint,
                       HistoryChunks& histories, const std::string& file, MPI_Comm comm)
    : Simulation(scene, comm, Unbuilt{}) {
  buildTables();
  // The shapes are rebuilt by the code that built them in the first run; a change in that code
  // or in the scene would silently change the continued run.
  if (const std::string diff = shapeMismatch(checkpoint.shapes, state_.shapes); !diff.empty()) {
    throw CheckpointError(cat(file, ": the shapes built from scene '", state_.scene.file,
                              "' differ from the stored ones (", diff, ")"));
  }
  // The faces' joint planes as the run had them: a file from before they were stored (layout
  // version 4) continues as it was written, without joints.
  restoreFacePlanes(checkpoint.shapes, state_.shapes, state_.scene.joint_planes.size(), file);
  if (checkpoint.dt != state_.scene.dt) {
    throw CheckpointError(cat(file, ": stored time step ", num(checkpoint.dt),
                              " s differs from the scene's ", num(state_.scene.dt), " s"));
  }
  if (checkpoint.materials.size() != state_.materials.size()) {
    throw CheckpointError(cat(file, ": ", checkpoint.materials.size(),
                              " stored materials, the scene has ", state_.materials.size()));
  }
  buildBolts();
  // A file of a layout without bolts (before version 6) holds no bolt state: it continues a scene
  // without bolts, or refuses one with them below.
  if (!state_.bolts.restore(checkpoint.bolt_states)) {
    throw CheckpointError(cat(file, ": ", checkpoint.bolt_states.size(),
                              " stored bolt joint states, the scene's [[bolt]]s cross ",
                              state_.bolts.jointCount(), " joints"));
  }
  buildLaws();
  computeExtents();
  restoreParticles(checkpoint, histories, file);
  suggestTimeStep();
  registerSteps();
  equilibrium_steps_ = checkpoint.equilibrium_steps;
  equilibrium_reached_ = checkpoint.equilibrium_reached;
  const ExactSum time = ExactSum::fromDigits(checkpoint.time_digits);
  if (checkpoint.stage == CheckpointStage::kEquilibrium) {
    if (!state_.scene.equilibrium.enabled) {
      throw CheckpointError(cat(file, ": written in the equilibrium stage, but scene '",
                                state_.scene.file, "' has no [equilibrium] stage"));
    }
    enterEquilibrium();
  } else {
    equilibrium_done_ = true;
  }
  state_.loop.restore(checkpoint.step, time);
  refreshGhosts(state_);
}

// The stored domain box and periodicity (they decide wrapping and what leaves the domain); the
// writer's blocks and rank map when the rank count is the same, else blocks fitted to the stored
// free particles for this rank count (the scene's blocks if it gives them), balanced on their
// counts. Then every particle to its owner and every history to the
// owners of its particles.
void Simulation::restoreParticles(const CheckpointData& checkpoint, HistoryChunks& histories,
                                  const std::string& file) {
  const auto& dom = checkpoint.domain;
  const domain::Aabb box{dom.lo, dom.hi};
  const bool same_ranks = dom.ranks == state_.ranks && !dom.rank_map.empty();
  for (const auto& p : checkpoint.particles) {
    if (p.shape < 0 || p.shape >= static_cast<int>(state_.shapes.size()) || p.material < 0 ||
        p.material >= static_cast<int>(state_.materials.size()) ||
        (p.isDriven() &&
         (p.driver < 0 || p.driver >= static_cast<int>(state_.scene.drivers.size())))) {
      throw CheckpointError(cat(file, ": particle ", p.uid,
                                " names a shape, material or driver the scene does not have"));
    }
    particles::Particle q = p;
    q.flags &= ~particles::kGhost;
    state_.storage.addLocal(q);
  }
  domain::Index3 counts = dom.blocks;
  if (!same_ranks) {
    if (state_.scene.domain.blocks) {
      counts = *state_.scene.domain.blocks;
    } else {  // blocks fitted to the particles, which every rank holds some of
      const domain::BlockForest whole(box, {1, 1, 1}, dom.periodic);
      std::vector<Vec3> centroids;
      for (std::size_t i = 0; i < state_.storage.localCount(); ++i) {
        const Vec3 x = whole.wrap(state_.storage[i].position);
        if (state_.storage[i].isFree() && box.contains(x)) centroids.push_back(x);
      }
      counts = fittedBlockCounts(state_, box, dom.periodic, centroids, /*collective=*/true);
    }
  }
  state_.forest = std::make_unique<domain::BlockForest>(box, counts, dom.periodic);
  if (same_ranks) {
    state_.forest->setRankMap(dom.rank_map, state_.ranks);
  } else {
    std::vector<double> weights(state_.forest->numBlocks(), 0.0);
    for (std::size_t i = 0; i < state_.storage.localCount(); ++i) {
      if (!state_.storage[i].isFree()) continue;
      const int b = state_.forest->blockOf(state_.forest->wrap(state_.storage[i].position));
      if (b >= 0) weights[b] += 1.0;  // outside: migrate() reports it
    }
    state_.forest->setRankMap(rankMap(state_, weights), state_.ranks);
  }
  state_.exchange.migrate(*state_.forest, state_.storage, state_.history, checkpoint.step);
  // Chunk by chunk: the records in transit stay bounded, and each chunk merges into the table in
  // place (the table's order and contents are those of one merge of all records).
  comm::HistoryRouter router(state_.storage, state_.comm);
  state_.history.clear();
  particles::HistoryRecords chunk;
  while (histories.next(chunk)) router.route(chunk, state_.history);
  restore_routing_ = router.stats();
  log::info(cat("restored step ", checkpoint.step, " (", toString(checkpoint.stage),
                " stage) from ", file, ", written by ", dom.ranks, " rank(s), on ", state_.ranks,
                " rank(s)"));
}

}  // namespace polydem::sim
