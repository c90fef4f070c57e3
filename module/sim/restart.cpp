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

#include "polydem/comm/history_routing.h"
#include "polydem/core/error.h"
#include "polydem/core/logging.h"
#include "polydem/core/mpi_env.h"
#include "polydem/core/strings.h"
#include "polydem/domain/rebalance.h"
#include "polydem/sim/simulation.h"

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

CheckpointData Simulation::checkpoint(const std::string& scene_toml, const std::string& scene_file,
                                      const std::string& run_state) const {
  requireBetweenSteps("checkpoint");
  CheckpointData d;
  d.scene_toml = scene_toml;
  d.scene_file = scene_file;
  d.step = loop_.step();
  d.time_digits = loop_.exactTime().digits();
  d.time = loop_.time();
  d.dt = dt();
  d.stage = stage_ == Stage::kEquilibrium ? CheckpointStage::kEquilibrium : CheckpointStage::kMain;
  d.equilibrium_steps = stage_ == Stage::kEquilibrium ? loop_.step() : equilibrium_steps_;
  d.equilibrium_reached = equilibrium_reached_;
  d.shapes = shapeRecords(shapes_);
  d.materials = scene_.materials;
  d.interactions = scene_.interactions;
  d.domain.lo = forest_->domain().lo;
  d.domain.hi = forest_->domain().hi;
  d.domain.blocks = forest_->counts();
  d.domain.periodic = forest_->periodic();
  d.domain.rank_map = forest_->rankMap();
  d.domain.ranks = ranks_;
  d.run_state = run_state;
  d.bolt_states = bolts_.states();
  for (std::size_t i = 0; i < storage_.localCount(); ++i) {
    const auto& p = storage_[i];
    if (p.isGlobal() && rank_ != 0) continue;  // replicated: rank 0's copy only
    d.particles.push_back(p);
  }
  const auto keys = history_.keys();
  const auto entries = history_.entries();
  particles::ContactHistory::Cursor cursor(history_);
  for (std::size_t k = 0; k < keys.size(); ++k) {
    if (!writesPair(storage_, keys[k], rank_)) continue;
    d.pair_keys.push_back(keys[k]);
    d.pair_histories.push_back(entries[k]);
    const auto [sub_keys, subs] = cursor.subs(keys[k]);
    for (const auto& s : sub_keys) d.sub_keys.push_back({keys[k], s.feature});
    d.sub_histories.insert(d.sub_histories.end(), subs.begin(), subs.end());
  }
  return d;
}

Simulation::Simulation(const setup::Setup& scene, const CheckpointData& checkpoint,
                       const std::string& file, MPI_Comm comm)
    : Simulation(scene, comm, Unbuilt{}) {
  buildTables();
  // The shapes are rebuilt by the code that built them in the first run; a change in that code
  // or in the scene would silently change the continued run.
  if (const std::string diff = shapeMismatch(checkpoint.shapes, shapes_); !diff.empty()) {
    throw CheckpointError(cat(file, ": the shapes built from scene '", scene_.file,
                              "' differ from the stored ones (", diff, ")"));
  }
  // The faces' joint planes as the run had them: a file from before they were stored (layout
  // version 4) continues as it was written, without joints.
  restoreFacePlanes(checkpoint.shapes, shapes_, scene_.joint_planes.size(), file);
  if (checkpoint.dt != scene_.dt) {
    throw CheckpointError(cat(file, ": stored time step ", num(checkpoint.dt),
                              " s differs from the scene's ", num(scene_.dt), " s"));
  }
  if (checkpoint.materials.size() != materials_.size()) {
    throw CheckpointError(cat(file, ": ", checkpoint.materials.size(),
                              " stored materials, the scene has ", materials_.size()));
  }
  buildBolts();
  // A file of a layout without bolts (before version 6) holds no bolt state: it continues a scene
  // without bolts, or refuses one with them below.
  if (!bolts_.restore(checkpoint.bolt_states)) {
    throw CheckpointError(cat(file, ": ", checkpoint.bolt_states.size(),
                              " stored bolt joint states, the scene's [[bolt]]s cross ",
                              bolts_.jointCount(), " joints"));
  }
  buildLaws();
  computeExtents();
  restoreParticles(checkpoint, file);
  suggestTimeStep();
  registerSteps();
  equilibrium_steps_ = checkpoint.equilibrium_steps;
  equilibrium_reached_ = checkpoint.equilibrium_reached;
  const ExactSum time = ExactSum::fromDigits(checkpoint.time_digits);
  if (checkpoint.stage == CheckpointStage::kEquilibrium) {
    if (!scene_.equilibrium.enabled) {
      throw CheckpointError(cat(file, ": written in the equilibrium stage, but scene '",
                                scene_.file, "' has no [equilibrium] stage"));
    }
    enterEquilibrium();
  } else {
    equilibrium_done_ = true;
  }
  loop_.restore(checkpoint.step, time);
  refreshGhosts();
}

// The stored domain box and periodicity (they decide wrapping and what leaves the domain); the
// writer's blocks and rank map when the rank count is the same, else blocks fitted to the stored
// free particles for this rank count (the scene's blocks if it gives them), balanced on their
// counts. Then every particle to its owner and every history to the
// owners of its particles.
void Simulation::restoreParticles(const CheckpointData& checkpoint, const std::string& file) {
  const auto& dom = checkpoint.domain;
  const domain::Aabb box{dom.lo, dom.hi};
  const bool same_ranks = dom.ranks == ranks_ && !dom.rank_map.empty();
  for (const auto& p : checkpoint.particles) {
    if (p.shape < 0 || p.shape >= static_cast<int>(shapes_.size()) || p.material < 0 ||
        p.material >= static_cast<int>(materials_.size()) ||
        (p.isDriven() && (p.driver < 0 || p.driver >= static_cast<int>(scene_.drivers.size())))) {
      throw CheckpointError(cat(file, ": particle ", p.uid,
                                " names a shape, material or driver the scene does not have"));
    }
    particles::Particle q = p;
    q.flags &= ~particles::kGhost;
    storage_.addLocal(q);
  }
  domain::Index3 counts = dom.blocks;
  if (!same_ranks) {
    if (scene_.domain.blocks) {
      counts = *scene_.domain.blocks;
    } else {  // blocks fitted to the particles, which every rank holds some of
      const domain::BlockForest whole(box, {1, 1, 1}, dom.periodic);
      std::vector<Vec3> centroids;
      for (std::size_t i = 0; i < storage_.localCount(); ++i) {
        const Vec3 x = whole.wrap(storage_[i].position);
        if (storage_[i].isFree() && box.contains(x)) centroids.push_back(x);
      }
      counts = fittedBlockCounts(box, dom.periodic, centroids, /*collective=*/true);
    }
  }
  forest_ = std::make_unique<domain::BlockForest>(box, counts, dom.periodic);
  if (same_ranks) {
    forest_->setRankMap(dom.rank_map, ranks_);
  } else {
    std::vector<double> weights(forest_->numBlocks(), 0.0);
    for (std::size_t i = 0; i < storage_.localCount(); ++i) {
      if (!storage_[i].isFree()) continue;
      const int b = forest_->blockOf(forest_->wrap(storage_[i].position));
      if (b >= 0) weights[b] += 1.0;  // outside: migrate() reports it
    }
    forest_->setRankMap(rankMap(weights), ranks_);
  }
  exchange_.migrate(*forest_, storage_, history_, checkpoint.step);
  particles::HistoryRecords records{checkpoint.pair_keys, checkpoint.pair_histories,
                                    checkpoint.sub_keys, checkpoint.sub_histories};
  history_ = comm::routeHistories(records, storage_, comm_);
  log::info(cat("restored step ", checkpoint.step, " (", toString(checkpoint.stage),
                " stage) from ", file, ", written by ", dom.ranks, " rank(s), on ", ranks_,
                " rank(s)"));
}

}  // namespace polydem::sim
