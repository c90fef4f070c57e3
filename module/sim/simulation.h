// Simulation: one run of a scene on the ranks of a communicator, in waLBerla's manner. Every rank
// holds the replicated tables (shapes, materials, drivers, block -> rank map), owns the free
// particles whose centroids lie in its blocks, sees ghost copies of its neighbours' particles and
// replicated fixed/driven bodies, and runs the same step: the named operators of
// sim/step/step_list.cpp over the state of sim/step/step_state.h, which this class owns.
//
// Simulation is the facade over that state: building it from a setup (simulation_setup.cpp),
// the stages (class Stages, stages.h), load balancing (class LoadBalancer, load_balancing.h),
// restart and checkpoint data (class Restart, restart.h), changes between steps
// (simulation_edit.cpp, force_operators.cpp). See
// contact_phase.h for why the result is the same bits on any number of ranks, and
// force_operator.h for the forces a user adds.
#pragma once

#include <mpi.h>

#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "polydem/broadphase/broad_phase.h"
#include "polydem/broadphase/cell_order.h"
#include "polydem/comm/history_routing.h"
#include "polydem/comm/particle_exchange.h"
#include "polydem/comm/state_hash.h"
#include "polydem/contact/contact.h"
#include "polydem/domain/block_forest.h"
#include "polydem/dynamics/contact_law.h"
#include "polydem/dynamics/monitors.h"
#include "polydem/particles/contact_history.h"
#include "polydem/particles/material.h"
#include "polydem/particles/particle_storage.h"
#include "polydem/setup/setup.h"
#include "polydem/sim/bolts.h"
#include "polydem/sim/contact_phase.h"
#include "polydem/sim/force_operator.h"
#include "polydem/sim/global_monitors.h"
#include "polydem/sim/ground_motion.h"
#include "polydem/sim/history_chunks.h"
#include "polydem/sim/load_balancing.h"
#include "polydem/sim/memory_use.h"
#include "polydem/sim/restart.h"
#include "polydem/sim/saved_state.h"
#include "polydem/sim/scene_operators.h"
#include "polydem/sim/stages.h"
#include "polydem/sim/step/step_state.h"
#include "polydem/timeloop/time_loop.h"

namespace polydem::sim {

/// Throws polydem::Error if `scene` has neither end_time nor steps (a scene changed from Python
/// may have neither): Simulation::run() and runScene() would never stop.
void requireStopCondition(const setup::Setup& scene);

class Simulation {
 public:
  /// `host`: the operators this program supplies for the scene's [[operator]]s that name no
  /// library (sim/scene_operators.h); the scene's operators are bound before anything is built.
  Simulation(const setup::Setup& scene, MPI_Comm comm, const HostOperators& host = {});
  /// Continues the run a checkpoint holds (collective, on any number of ranks): `checkpoint` is
  /// what checkpoint::readCheckpoint returned on this rank, `scene` the scene it was written from
  /// (its stop settings may differ). The particles move to their owners by position, the pair
  /// histories to the owners of their particles, and step, exact time, stage and leapfrog
  /// velocities are taken as stored, so that stepping on gives the same bits as a run that never
  /// stopped (sim/restart.cpp). Throws CheckpointError naming `file` if the shapes
  /// built from `scene` differ from the stored ones, or the time step does.
  Simulation(const setup::Setup& scene, const CheckpointData& checkpoint, const std::string& file,
             MPI_Comm comm, const HostOperators& host = {});
  /// The same with the pair histories handed over in bounded chunks (sim/history_chunks.h; the
  /// pair and sub-contact tables of `checkpoint` are not read): each chunk is routed to the owners
  /// and merged in place, so that the restart holds little more than the run's own history.
  Simulation(const setup::Setup& scene, const CheckpointData& checkpoint, HistoryChunks& histories,
             const std::string& file, MPI_Comm comm, const HostOperators& host = {});
  ~Simulation();
  Simulation(const Simulation&) = delete;
  Simulation& operator=(const Simulation&) = delete;

  /// Runs (or, after a restart in that stage, continues) the initial-equilibrium stage if the
  /// scene asks for it and it has not ended yet; returns its step count so far. A stage stopped
  /// by the step hook stays open (stage() == kEquilibrium) and may be continued by calling again.
  std::int64_t runEquilibrium();
  /// Runs the main stage until the scene's end time or step count (or a stop callback).
  timeloop::StopReason run();
  /// Advances one step of the current stage.
  void step();

  // --- state, for monitors, checks, output and tests --------------------------------------
  /// The setup it was built from, without the shapes' vertex lists and face planes (empty: the
  /// shape table, shapes(), holds the shapes; the caller's setup keeps them).
  const setup::Setup& scene() const { return state_.scene; }
  MPI_Comm comm() const { return state_.comm; }
  Stage stage() const { return state_.stage; }
  std::int64_t stepCount() const { return state_.loop.step(); }
  double time() const { return state_.loop.time(); }
  double dt() const { return state_.scene.dt; }
  std::int64_t equilibriumSteps() const { return stages_.equilibriumSteps(); }
  bool equilibriumReached() const { return stages_.equilibriumReached(); }
  /// Timing of the equilibrium stage (the main stage's is loop().timing()).
  const TimingPool& equilibriumTiming() const { return stages_.equilibriumTiming(); }
  const particles::ShapeTable& shapes() const { return state_.shapes; }
  const particles::MaterialTable& materials() const { return state_.materials; }
  const particles::ParticleStorage& particles() const { return state_.storage; }
  const particles::ContactHistory& history() const { return state_.history; }
  const domain::BlockForest& forest() const { return *state_.forest; }
  const ContactPhase& contacts() const { return state_.contact_phase; }
  /// Whether the contact phase keeps a full record of every evaluated pair (contacts().records():
  /// snapshots' contacts, tracked particles, contact checks); on by default. A run that reads
  /// none turns them off; the physics and the load model do not read them.
  void keepContactRecords(bool keep) { state_.contact_phase.keepRecords(keep); }
  const ContactPhaseStats& contactStats() const { return state_.contact_stats; }
  const comm::ExchangeStats& exchangeStats() const { return state_.exchange_stats; }
  /// False: every exchange sends every ghost whole instead of updating the ones that stay (the
  /// same bits, more bytes; comm/ghost_channels.h). For comparisons; set it alike on all ranks.
  void setCompactGhosts(bool on) { state_.exchange.setCompactGhosts(on); }
  /// This rank's exchanges summed over the steps since the start (or the restart).
  const comm::ExchangeStats& exchangeTotals() const { return state_.exchange_totals; }
  /// Pair histories this rank received with migrating particles since the start.
  std::int64_t migratedHistories() const { return state_.migrated_histories; }
  timeloop::TimeLoop& loop() { return state_.loop; }
  const timeloop::TimeLoop& loop() const { return state_.loop; }
  const contact::Kernel& kernel() const { return *state_.kernel; }
  /// The scene's [[bolt]]s and their state (sim/bolts.h).
  const Bolts& bolts() const { return state_.bolts; }
  /// A line per joint of every bolt at the current poses, with its axial force (collective).
  std::vector<BoltLine> boltLines() const {
    return state_.bolts.lines(state_.storage, state_.comm);
  }

  /// The centroid (world frame) particle `spec` of the scene starts at, as placeParticles() puts
  /// it.
  Vec3 initialCentroid(const setup::ParticleSpec& spec) const {
    return spec.position + spec.orientation * state_.shape_frames[spec.shape].centroid;
  }
  /// The orientation (body -> world) particle `spec` starts with.
  Quat initialOrientation(const setup::ParticleSpec& spec) const {
    return (spec.orientation * state_.shape_frames[spec.shape].rotation).normalized();
  }
  /// Mass and principal inertia of local or ghost entry i.
  dynamics::MassProperties massProperties(std::size_t i) const { return state_.massProperties(i); }
  /// Global monitors (collective).
  GlobalMonitors monitors() const { return globalMonitors(state_); }
  double forceRatio() const { return globalForceRatio(state_); }  // collective
  /// Hash of the whole state, the same on any rank count (collective).
  comm::StateHash stateHash() const;

  /// Called after every step (all ranks), e.g. by checks and output, once stepCount() and time()
  /// count the step: positions are those at time(), leapfrog velocities those at time() - dt/2,
  /// and contacts() those the step evaluated, at the positions of time() - dt.
  void addObserver(std::function<void()> observer) {
    state_.observers.push_back(std::move(observer));
  }
  /// Called on every rank after every step of either stage, once the step is complete (step
  /// count and time advanced, particles migrated, ghosts fresh): the place to write a
  /// checkpoint. Returning true (the same on every rank) stops the current stage's loop with
  /// StopReason::kUserCondition; the stage can be continued or checkpointed.
  void setStepHook(std::function<bool()> hook) { stages_.setStepHook(std::move(hook)); }
  /// Adds a force to every step from now on (force_operator.h): `op` runs on every rank after
  /// the contact forces and gravity, before integration, after the operators added before it,
  /// as an operator of the step timed under `name` (which may not be a step operator's name).
  /// Added before the first step (collective then: every rank adds the same operators), it also
  /// gets its share of the leapfrog's start, so a constant force acts from t = 0 exactly.
  /// Throws polydem::Error if `name` is empty or already taken. With no operator the step is the
  /// same bits as before operators existed.
  void addForceOperator(std::string name, ForceOperator op);
  /// The names of the force operators, in the order they run.
  std::vector<std::string> forceOperatorNames() const;
  /// Throws polydem::Error naming `what` and the operator when called from inside a force
  /// operator: the step that called it is half done (its forces summed, its particles not yet
  /// moved), so stepping, changing or checkpointing the simulation there would change the run
  /// behind the step's back or store half a step. Every state-changing method calls it first.
  void requireBetweenSteps(std::string_view what) const;

  /// The farthest any point of a free particle may move in one step: the ghost range (the
  /// largest free circumradius plus the contact margin), the most the exchange between ranks
  /// follows (comm/particle_exchange.h). The same on any rank count.
  double stepReach() const { return state_.ghost_range; }

  /// Sets the velocity and/or angular velocity [rad/s, world frame] of the free particle `uid`
  /// between steps, as the leapfrog holds them (at time() - dt/2): a driving script's change of
  /// state, which a checkpoint then keeps. Collective, with the same arguments on every rank: the
  /// owner changes it and the ghosts are refreshed, so the next step sees it on any rank count.
  /// Returns false (on every rank) if no rank owns a free particle `uid`. Throws polydem::Error
  /// ("particle <uid>: ...", on every rank, changing nothing) for a value that is not finite or
  /// would move a point of the particle more than stepReach() in one step: |v| dt, or |w| r dt
  /// with r its circumradius (sim/simulation_edit.cpp).
  bool setVelocity(Uid uid, const std::optional<Vec3>& velocity,
                   const std::optional<Vec3>& angular_velocity);

  /// This rank's part of a checkpoint of the current state (not collective): replicated tables,
  /// this rank's free particles (and the fixed/driven ones on rank 0), each pair history once
  /// over all ranks. Call between steps. `scene_toml` and `scene_file` are stored as given.
  CheckpointData checkpoint(const std::string& scene_toml, const std::string& scene_file,
                            const std::string& run_state) const {
    requireBetweenSteps("checkpoint");
    CheckpointData d = Restart::capture(state_, stages_, scene_toml, scene_file, run_state);
    Restart::copyHistories(state_, d);
    return d;
  }
  /// The same with the pair histories left in this simulation's table (CheckpointData::
  /// history_view) instead of copied, so that writing the checkpoint holds no second copy of the
  /// history: for writing at once, before the next step.
  CheckpointData checkpointForWriting(const std::string& scene_toml, const std::string& scene_file,
                                      const std::string& run_state) const {
    requireBetweenSteps("checkpoint");
    CheckpointData d = Restart::capture(state_, stages_, scene_toml, scene_file, run_state);
    d.history_view = Restart::historyView(state_);
    return d;
  }

  /// Weighs a new decomposition against the current one by the work of the last contact phase
  /// (sim/load_balance.h) and, if it is better by the margin, installs it and moves the particles
  /// (collective; see docs/domain.md). Returns whether it was adopted.
  bool rebalance() {
    requireBetweenSteps("rebalance");
    return state_.balancer.rebalance(state_);
  }
  /// What the rebalancing did so far (the initial one at step 0 included).
  using BalanceLog = sim::BalanceLog;
  const BalanceLog& balanceLog() const { return state_.balancer.log(); }
  const LoadModel& loadModel() const { return state_.balancer.model(); }
  /// The load model's cost of this rank's last contact phase and particles.
  const StepWork& lastWork() const { return state_.balancer.lastWork(); }
  /// The exchanges of the steps alone (not those of the start or of a rebalancing between
  /// steps), and how many steps they were.
  const comm::ExchangeStats& stepExchangeTotals() const { return state_.step_exchange_totals; }
  std::int64_t exchanges() const { return state_.exchanges; }
  /// Seconds this rank spent on the next steps' early contact work inside the exchanges (the
  /// loop's "early contacts" timer, over both stages).
  double earlySeconds() const { return state_.early_seconds; }

  /// Puts this rank's local particles in storage in the order `order` gives (order[k]: the
  /// storage index of the particle that goes to index k; a permutation of [0,
  /// particles().localCount())), between steps; not collective. No result changes: pairs are
  /// evaluated and summed in uid order (contact_phase.h). The step does this itself into the
  /// broad phase's cell order (scene domain.sort_every); tests shuffle with it.
  void reorderParticles(std::span<const std::int32_t> order) {
    requireBetweenSteps("reorderParticles");
    state_.storage.permuteLocals(order);
  }
  /// How many times the step reordered this rank's particles into cell order.
  std::int64_t sorts() const { return state_.sorts; }

  /// The dt suggested from masses and stiffnesses (see dynamics/time_step.h).
  double suggestedTimeStep() const { return suggested_dt_; }

  /// This rank's heap bytes by structure (sim/memory_use.h), from capacities: particles, shapes,
  /// scene copy, broad phase, pair list, contact history (pairs, sub-contacts), per-particle
  /// kernel caches, contact records, forces, exchange buffers. Not collective.
  MemoryUse memoryUse() const;
  /// How the restart that built this routed the pair histories (chunks, the most bytes one chunk
  /// held in transit on this rank); all zero for a simulation built from a scene.
  const comm::HistoryRoutingStats& restoreRouting() const { return restore_routing_; }

 private:
  /// Members that depend only on the scene, the communicator and the scene's operators; both
  /// public constructors delegate here, then build the rest (from the scene, or from a
  /// checkpoint).
  struct Unbuilt {};
  Simulation(const setup::Setup& scene, MPI_Comm comm, const HostOperators& host, Unbuilt);
  void buildTables();
  void releaseShapeSpecs();
  void buildDomain();
  void placeParticles();
  void buildLaws();
  void buildJointLaws();  // the joints' coefficients, from buildLaws()
  void buildBolts();      // the bolts' crossings, from the scene's initial poses
  domain::Aabb computeExtents();
  void checkFreeBodies() const;
  void suggestTimeStep();
  void startLeapfrogWith(const std::string& name, const ForceOperator& op);

  StepState state_;  // what the step's operators act on (sim/step/step_state.h)
  Stages stages_;    // the stages over state_ (sim/stages.h)
  comm::HistoryRoutingStats restore_routing_;  // of the restart that built this, if one did
  double suggested_dt_ = 0.0;
};

}  // namespace polydem::sim
