// A run's state to and from its saved state (restart.h).
#include "polydem/sim/restart.h"

#include <algorithm>
#include <limits>

#include "polydem/comm/history_routing.h"
#include "polydem/core/error.h"
#include "polydem/core/exact_sum.h"
#include "polydem/core/logging.h"
#include "polydem/core/mpi_env.h"
#include "polydem/core/strings.h"
#include "polydem/domain/rebalance.h"
#include "polydem/sim/load_balancing.h"
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

CheckpointData Restart::capture(const StepState& s, const Stages& stages,
                                const std::string& scene_toml, const std::string& scene_file,
                                const std::string& run_state) {
  CheckpointData d;
  d.scene_toml = scene_toml;
  d.scene_file = scene_file;
  d.step = s.loop.step();
  d.time_digits = s.loop.exactTime().digits();
  d.time = s.loop.time();
  d.dt = s.dt();
  d.stage = s.stage == Stage::kEquilibrium ? CheckpointStage::kEquilibrium : CheckpointStage::kMain;
  d.equilibrium_steps = s.stage == Stage::kEquilibrium ? s.loop.step() : stages.equilibriumSteps();
  d.equilibrium_reached = stages.equilibriumReached();
  d.shapes = shapeRecords(s.shapes);
  d.materials = s.scene.materials;
  d.interactions = s.scene.interactions;
  d.domain.lo = s.forest->domain().lo;
  d.domain.hi = s.forest->domain().hi;
  d.domain.blocks = s.forest->counts();
  d.domain.periodic = s.forest->periodic();
  d.domain.rank_map = s.forest->rankMap();
  d.domain.ranks = s.ranks;
  d.run_state = run_state;
  d.bolt_states = s.bolts.states();
  for (std::size_t i = 0; i < s.storage.localCount(); ++i) {
    const auto& p = s.storage[i];
    if (p.isGlobal() && s.rank != 0) continue;  // replicated: rank 0's copy only
    d.particles.push_back(p);
  }
  return d;
}

HistoryView Restart::historyView(const StepState& s) {
  HistoryView view;
  view.table = &s.history;
  const auto keys = s.history.keys();
  if (keys.size() > std::numeric_limits<std::uint32_t>::max()) {
    throw Error(cat("checkpoint: ", keys.size(), " pair histories on rank ", s.rank,
                    ", more than a checkpoint's index of them counts"));
  }
  for (std::size_t k = 0; k < keys.size(); ++k) {
    if (writesPair(s.storage, keys[k], s.rank)) view.pairs.push_back(static_cast<std::uint32_t>(k));
  }
  return view;
}

void Restart::copyHistories(const StepState& s, CheckpointData& d) {
  particles::HistoryRecords records;
  for (std::uint32_t k : historyView(s).pairs) s.history.copyPair(k, records);
  d.pair_keys = std::move(records.keys);
  d.pair_histories = std::move(records.entries);
  d.sub_keys = std::move(records.sub_keys);
  d.sub_histories = std::move(records.sub_entries);
}

void Restart::checkTables() const {
  // The shapes are rebuilt by the code that built them in the first run; a change in that code
  // or in the scene would silently change the continued run.
  if (const std::string diff = shapeMismatch(c_.shapes, s_.shapes); !diff.empty()) {
    throw CheckpointError(cat(file_, ": the shapes built from scene '", s_.scene.file,
                              "' differ from the stored ones (", diff, ")"));
  }
  // The faces' joint planes as the run had them: a file from before they were stored (layout
  // version 4) continues as it was written, without joints.
  restoreFacePlanes(c_.shapes, s_.shapes, s_.scene.joint_planes.size(), file_);
  if (c_.dt != s_.scene.dt) {
    throw CheckpointError(cat(file_, ": stored time step ", num(c_.dt),
                              " s differs from the scene's ", num(s_.scene.dt), " s"));
  }
  if (c_.materials.size() != s_.materials.size()) {
    throw CheckpointError(cat(file_, ": ", c_.materials.size(), " stored materials, the scene has ",
                              s_.materials.size()));
  }
}

void Restart::restoreBolts() const {
  // A file of a layout without bolts (before version 6) holds no bolt state: it continues a scene
  // without bolts, or refuses one with them below.
  if (!s_.bolts.restore(c_.bolt_states)) {
    throw CheckpointError(cat(file_, ": ", c_.bolt_states.size(),
                              " stored bolt joint states, the scene's [[bolt]]s cross ",
                              s_.bolts.jointCount(), " joints"));
  }
}

// Every stored particle as a local one here; migration then takes each to its owner.
void Restart::addParticles() const {
  for (const auto& p : c_.particles) {
    if (p.shape < 0 || p.shape >= static_cast<int>(s_.shapes.size()) || p.material < 0 ||
        p.material >= static_cast<int>(s_.materials.size()) ||
        (p.isDriven() && (p.driver < 0 || p.driver >= static_cast<int>(s_.scene.drivers.size())))) {
      throw CheckpointError(cat(file_, ": particle ", p.uid,
                                " names a shape, material or driver the scene does not have"));
    }
    particles::Particle q = p;
    q.flags &= ~particles::kGhost;
    s_.storage.addLocal(q);
  }
}

// The writer's blocks when the rank count is the same, else the scene's blocks if it gives them,
// else blocks fitted to the stored free particles (which every rank holds some of).
domain::Index3 Restart::blockCounts(const domain::Aabb& box, bool same_ranks) const {
  const auto& dom = c_.domain;
  if (same_ranks) return dom.blocks;
  if (s_.scene.domain.blocks) return *s_.scene.domain.blocks;
  const domain::BlockForest whole(box, {1, 1, 1}, dom.periodic);
  std::vector<Vec3> centroids;
  for (std::size_t i = 0; i < s_.storage.localCount(); ++i) {
    const Vec3 x = whole.wrap(s_.storage[i].position);
    if (s_.storage[i].isFree() && box.contains(x)) centroids.push_back(x);
  }
  return fittedBlockCounts(s_, box, dom.periodic, centroids, /*collective=*/true);
}

// The stored domain box and periodicity (they decide wrapping and what leaves the domain); the
// writer's rank map when the rank count is the same, else one balanced on the particle counts.
// Then every particle to its owner and every history to the owners of its particles.
comm::HistoryRoutingStats Restart::restoreParticles(HistoryChunks& histories) const {
  const auto& dom = c_.domain;
  const domain::Aabb box{dom.lo, dom.hi};
  const bool same_ranks = dom.ranks == s_.ranks && !dom.rank_map.empty();
  addParticles();
  s_.forest =
      std::make_unique<domain::BlockForest>(box, blockCounts(box, same_ranks), dom.periodic);
  if (same_ranks) {
    s_.forest->setRankMap(dom.rank_map, s_.ranks);
  } else {
    std::vector<double> weights(s_.forest->numBlocks(), 0.0);
    for (std::size_t i = 0; i < s_.storage.localCount(); ++i) {
      if (!s_.storage[i].isFree()) continue;
      const int b = s_.forest->blockOf(s_.forest->wrap(s_.storage[i].position));
      if (b >= 0) weights[b] += 1.0;  // outside: migrate() reports it
    }
    s_.forest->setRankMap(rankMap(s_, weights), s_.ranks);
  }
  s_.exchange.migrate(*s_.forest, s_.storage, s_.history, c_.step);
  // Chunk by chunk: the records in transit stay bounded, each chunk's records are appended to
  // the table, and the table is sorted once at the end (the table's order and contents are those
  // of one merge of all records).
  comm::HistoryRouter router(s_.storage, s_.comm);
  s_.history.beginAssembly();
  particles::HistoryRecords chunk;
  while (histories.next(chunk)) router.route(chunk, s_.history);
  router.finish(s_.history);
  log::info(cat("restored step ", c_.step, " (", toString(c_.stage), " stage) from ", file_,
                ", written by ", dom.ranks, " rank(s), on ", s_.ranks, " rank(s)"));
  return router.stats();
}

void Restart::restoreStage(Stages& stages) const {
  const bool in_equilibrium = c_.stage == CheckpointStage::kEquilibrium;
  if (in_equilibrium && !s_.scene.equilibrium.enabled) {
    throw CheckpointError(cat(file_, ": written in the equilibrium stage, but scene '",
                              s_.scene.file, "' has no [equilibrium] stage"));
  }
  stages.restore(c_.equilibrium_steps, c_.equilibrium_reached, in_equilibrium);
  s_.loop.restore(c_.step, ExactSum::fromDigits(c_.time_digits));
  refreshGhosts(s_);
}

}  // namespace polydem::sim
