// Simulation: one run of a scene on the ranks of a communicator, in waLBerla's manner. Every rank
// holds the replicated tables (shapes, materials, drivers, block -> rank map), owns the free
// particles whose centroids lie in its blocks, sees ghost copies of its neighbours' particles and
// replicated fixed/driven bodies, and runs the same timeloop:
//
//   sort (now and then) -> derived -> broadphase -> contacts -> gravity (+ seismic) -> water
//   -> bolts -> force operators -> integrate -> communicate -> monitors
//
// (see contact_phase.h for why the result is the same bits on any number of ranks, and
// force_operator.h for the forces a user adds).
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
#include "polydem/sim/ground_motion.h"
#include "polydem/sim/load_balance.h"
#include "polydem/sim/memory_use.h"
#include "polydem/sim/saved_state.h"
#include "polydem/timeloop/time_loop.h"

namespace polydem::sim {

/// Throws polydem::Error if `scene` has neither end_time nor steps (a scene changed from Python
/// may have neither): Simulation::run() and runScene() would never stop.
void requireStopCondition(const setup::Setup& scene);

/// The two stages of a run (Keissar section 3.3, after 3DEC): an optional initial-equilibrium
/// stage with heavy damping and high friction, then the scene's own values.
enum class Stage { kEquilibrium, kMain };

/// Global values of the current state, the same on every rank.
struct GlobalMonitors {
  double kinetic_energy = 0.0;
  double force_ratio = 0.0;
  std::int64_t contacts = 0;   // touching pairs, each counted once
  std::int64_t particles = 0;  // free particles
  double max_speed = 0.0;
  double mean_speed = 0.0;
};

class Simulation {
 public:
  Simulation(const setup::Setup& scene, MPI_Comm comm);
  /// Continues the run a checkpoint holds (collective, on any number of ranks): `checkpoint` is
  /// what io::readCheckpoint returned on this rank, `scene` the scene it was written from (its
  /// stop settings may differ). The particles move to their owners by position, the pair
  /// histories to the owners of their particles, and step, exact time, stage and leapfrog
  /// velocities are taken as stored, so that stepping on gives the same bits as a run that never
  /// stopped (sim/simulation_checkpoint.cpp). Throws CheckpointError naming `file` if the shapes
  /// built from `scene` differ from the stored ones, or the time step does.
  Simulation(const setup::Setup& scene, const CheckpointData& checkpoint, const std::string& file,
             MPI_Comm comm);
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
  const setup::Setup& scene() const { return scene_; }
  MPI_Comm comm() const { return comm_; }
  Stage stage() const { return stage_; }
  std::int64_t stepCount() const { return loop_.step(); }
  double time() const { return loop_.time(); }
  double dt() const { return scene_.dt; }
  std::int64_t equilibriumSteps() const { return equilibrium_steps_; }
  bool equilibriumReached() const { return equilibrium_reached_; }
  /// Timing of the equilibrium stage (the main stage's is loop().timing()).
  const TimingPool& equilibriumTiming() const { return equilibrium_timing_; }
  const particles::ShapeTable& shapes() const { return shapes_; }
  const particles::MaterialTable& materials() const { return materials_; }
  const particles::ParticleStorage& particles() const { return storage_; }
  const particles::ContactHistory& history() const { return history_; }
  const domain::BlockForest& forest() const { return *forest_; }
  const ContactPhase& contacts() const { return contact_phase_; }
  const ContactPhaseStats& contactStats() const { return contact_stats_; }
  const comm::ExchangeStats& exchangeStats() const { return exchange_stats_; }
  /// False: every exchange sends every ghost whole instead of updating the ones that stay (the
  /// same bits, more bytes; comm/ghost_channels.h). For comparisons; set it alike on all ranks.
  void setCompactGhosts(bool on) { exchange_.setCompactGhosts(on); }
  /// This rank's exchanges summed over the steps since the start (or the restart).
  const comm::ExchangeStats& exchangeTotals() const { return exchange_totals_; }
  /// Pair histories this rank received with migrating particles since the start.
  std::int64_t migratedHistories() const { return migrated_histories_; }
  timeloop::TimeLoop& loop() { return loop_; }
  const timeloop::TimeLoop& loop() const { return loop_; }
  const contact::Kernel& kernel() const { return *kernel_; }
  /// The scene's [[bolt]]s and their state (sim/bolts.h).
  const Bolts& bolts() const { return bolts_; }
  /// A line per joint of every bolt at the current poses, with its axial force (collective).
  std::vector<BoltLine> boltLines() const { return bolts_.lines(storage_, comm_); }

  /// The centroid (world frame) particle `spec` of the scene starts at, as placeParticles() puts
  /// it.
  Vec3 initialCentroid(const setup::ParticleSpec& spec) const {
    return spec.position + spec.orientation * shape_frames_[spec.shape].centroid;
  }
  /// The orientation (body -> world) particle `spec` starts with.
  Quat initialOrientation(const setup::ParticleSpec& spec) const {
    return (spec.orientation * shape_frames_[spec.shape].rotation).normalized();
  }
  /// Mass and principal inertia of local or ghost entry i.
  dynamics::MassProperties massProperties(std::size_t i) const;
  /// Global monitors (collective).
  GlobalMonitors monitors();
  /// Hash of the whole state, the same on any rank count (collective).
  comm::StateHash stateHash() const;

  /// Called after every step (all ranks), e.g. by checks and output, once stepCount() and time()
  /// count the step: positions are those at time(), leapfrog velocities those at time() - dt/2,
  /// and contacts() those the step evaluated, at the positions of time() - dt.
  void addObserver(std::function<void()> observer) { observers_.push_back(std::move(observer)); }
  /// Called on every rank after every step of either stage, once the step is complete (step
  /// count and time advanced, particles migrated, ghosts fresh): the place to write a
  /// checkpoint. Returning true (the same on every rank) stops the current stage's loop with
  /// StopReason::kUserCondition; the stage can be continued or checkpointed.
  void setStepHook(std::function<bool()> hook) { step_hook_ = std::move(hook); }
  /// Adds a force to every step from now on (force_operator.h): `op` runs on every rank after
  /// the contact forces and gravity, before integration, after the operators added before it.
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
  double stepReach() const { return ghost_range_; }

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
                            const std::string& run_state) const;

  /// Weighs a new decomposition against the current one by the work of the last contact phase
  /// (sim/load_balance.h) and, if it is better by the margin, installs it and moves the particles
  /// (collective; see docs/domain.md). Returns whether it was adopted.
  bool rebalance();
  /// What the rebalancing did so far (the initial one at step 0 included).
  struct BalanceLog {
    std::int64_t checks = 0;      // times the imbalance was looked at
    std::int64_t proposals = 0;   // times a new decomposition was computed
    std::int64_t adopted = 0;     // times it was installed
    double last_imbalance = 1.0;  // the work's imbalance at the last check (max / mean)
  };
  const BalanceLog& balanceLog() const { return balance_log_; }
  const LoadModel& loadModel() const { return load_model_; }
  /// The load model's cost of this rank's last contact phase and particles.
  const StepWork& lastWork() const { return last_work_; }
  /// The exchanges of the steps alone (not those of the start or of a rebalancing between
  /// steps), and how many steps they were.
  const comm::ExchangeStats& stepExchangeTotals() const { return step_exchange_totals_; }
  std::int64_t exchanges() const { return exchanges_; }
  /// Seconds this rank spent on the next steps' early contact work inside the exchanges (part
  /// of the loop's "communicate" timer, not the exchange's own time).
  double earlySeconds() const { return early_seconds_; }

  /// Puts this rank's local particles in storage in the order `order` gives (order[k]: the
  /// storage index of the particle that goes to index k; a permutation of [0,
  /// particles().localCount())), between steps; not collective. No result changes: pairs are
  /// evaluated and summed in uid order (contact_phase.h). The step does this itself into the
  /// broad phase's cell order (scene domain.sort_every); tests shuffle with it.
  void reorderParticles(std::span<const std::int32_t> order) {
    requireBetweenSteps("reorderParticles");
    storage_.permuteLocals(order);
  }
  /// How many times the step reordered this rank's particles into cell order.
  std::int64_t sorts() const { return sorts_; }

  /// The dt suggested from masses and stiffnesses (see dynamics/time_step.h).
  double suggestedTimeStep() const { return suggested_dt_; }

  /// This rank's heap bytes by structure (sim/memory_use.h), from capacities: particles, shapes,
  /// scene copy, broad phase, pair list, contact history (pairs, sub-contacts), per-particle
  /// kernel caches, contact records, forces, exchange buffers. Not collective.
  MemoryUse memoryUse() const;

 private:
  /// Members that depend only on the scene and the communicator; both public constructors
  /// delegate here, then build the rest (from the scene, or from a checkpoint).
  struct Unbuilt {};
  Simulation(const setup::Setup& scene, MPI_Comm comm, Unbuilt);
  std::vector<int> rankMap(std::span<const double> weights) const;
  domain::PartitionMethod partitionMethod() const;
  /// Block counts for `box` from the free particles' centroids; `collective`: each rank holds
  /// some of them (sim/simulation_balance.cpp).
  domain::Index3 fittedBlockCounts(const domain::Aabb& box, const domain::Periodic& periodic,
                                   std::span<const Vec3> centroids, bool collective) const;
  /// The collective part of rebalance(): installs a better decomposition, moves nothing.
  bool balanceDecomposition();
  void buildTables();
  void buildDomain();
  void placeParticles();
  void buildLaws();
  void buildJointLaws();  // the joints' coefficients, from buildLaws()
  void buildBolts();      // the bolts' crossings, from the scene's initial poses
  void registerSteps();
  void startLeapfrog();
  void enterEquilibrium();
  domain::Aabb computeExtents();
  void checkFreeBodies() const;
  void suggestTimeStep();
  void restoreParticles(const CheckpointData& checkpoint, const std::string& file);

  void updateDerived();
  double fillSphereSet();
  void sortParticles();
  void findCandidates();
  /// The broad phase's pairs over the particles stored now.
  void findPairs(std::vector<broadphase::CandidatePair>& out);
  /// The contact phase's setup for the current stage and time.
  ContactSetup contactSetup() const;
  /// The early part of the next contact phase, while the exchange is in flight.
  void evaluateEarly();
  /// Fresh ghosts after a change of state between steps; forgets the early contact work.
  void refreshGhosts();
  void computeContacts();
  void applyForceOperators();
  /// Calls `op` marked as running (requireBetweenSteps refuses meanwhile).
  void callForceOperator(const std::string& name, const ForceOperator& op, const ForceStep& step);
  void startLeapfrogWith(const std::string& name, const ForceOperator& op);
  void integrate();
  void moveWithGround();
  void checkParticlesInside(std::int64_t step) const;
  void communicate();
  void observe();

  setup::Setup scene_;
  MPI_Comm comm_;
  int rank_ = 0, ranks_ = 1;
  Stage stage_ = Stage::kMain;
  std::int64_t equilibrium_steps_ = 0;
  bool equilibrium_reached_ = false;
  bool equilibrium_done_ = false;  // the stage has ended (or never was), never to run again
  TimingPool equilibrium_timing_;

  struct ShapeFrame {
    Quat rotation;  // body frame -> the frame the scene gave the shape in
    Vec3 centroid;  // in that frame
  };
  particles::ShapeTable shapes_;
  std::vector<ShapeFrame> shape_frames_;
  particles::MaterialTable materials_;
  std::vector<double> densities_;
  std::vector<dynamics::LawCoefficients> law_main_, law_equilibrium_;
  // Joints: joint plane -> [[joint]] (-1: none), and coefficients per joint and material pair
  // (sim/pair_law.h PairJoints); empty for a scene without joints.
  std::vector<std::int32_t> plane_joint_;
  std::vector<dynamics::LawCoefficients> joint_law_main_, joint_law_equilibrium_;
  Bolts bolts_;  // replicated on every rank (sim/bolts.h)
  std::optional<GroundMotion> ground_;  // [seismic] record: moves the fixed particles
  std::unique_ptr<contact::Kernel> kernel_;
  std::unique_ptr<broadphase::BroadPhase> broadphase_;
  std::unique_ptr<domain::BlockForest> forest_;
  comm::ParticleExchange exchange_;
  double ghost_range_ = 0.0;  // largest free circumradius + margin
  double r_free_ = 0.0;       // largest free circumradius
  LoadModel load_model_;
  BalanceLog balance_log_;
  bool sample_load_ = false;  // sample the next contact phase's work for a balance check
  LoadSample load_sample_;
  StepWork last_work_;
  comm::ExchangeStats step_exchange_totals_;
  std::int64_t exchanges_ = 0;
  double margin_ = 0.0;  // absolute contact margin
  dynamics::ContactModel contact_model_ = dynamics::ContactModel::kSubContacts;
  bool overlap_centroid_ = false;  // contact_point = "overlap-centroid"
  double suggested_dt_ = 0.0;

  particles::ParticleStorage storage_;
  particles::ContactHistory history_;
  ContactPhase contact_phase_;
  ContactPhaseStats contact_stats_;
  comm::ExchangeStats exchange_stats_;
  comm::ExchangeStats exchange_totals_;
  std::int64_t migrated_histories_ = 0;
  std::vector<dynamics::ForceAccumulator> forces_;  // parallel to storage_ during a step only
  dynamics::ForceRatio ratio_local_;  // this rank's share of Keissar eq. 3.2, last contact phase
  std::vector<broadphase::CandidatePair> candidates_;
  std::vector<broadphase::CandidatePair> early_candidates_;  // evaluateEarly()'s
  double early_seconds_ = 0.0;  // spent in evaluateEarly() since the start
  std::vector<Vec3> centers_;
  std::vector<double> radii_;
  std::vector<Uid> uids_;
  std::vector<std::uint8_t> active_;
  broadphase::CellOrder cell_order_;
  std::int64_t sorts_ = 0;
  bool sort_started_ = false;  // sortParticles() ran at this object's first step

  timeloop::TimeLoop loop_;
  timeloop::TimeLoop parked_loop_;  // the main stage's loop while the equilibrium stage runs
  std::vector<std::function<void()>> observers_;
  std::function<bool()> step_hook_;
  struct NamedForceOperator {
    std::string name;
    ForceOperator apply;
  };
  std::vector<NamedForceOperator> force_operators_;
  bool leapfrog_fresh_ = false;                    // started from the setup and not stepped since
  const std::string* running_operator_ = nullptr;  // the force operator being called, if any
};

}  // namespace polydem::sim
