// The state one step acts on: everything the step's operators (sim/step/operators.h) read and
// change, in one struct they take, so that an operator's inputs are visible in its signature's
// one argument and in this file, not scattered over an engine object. sim::Simulation owns one
// and is a facade over it (building, stages, restart, edits between steps).
//
// Grouped by lifetime: what the setup builds once (tables, laws, kernel, grids), the particles
// and their decomposition (the run's state proper: what a checkpoint stores), and the scratch
// and statistics of the step (recomputed every step from the run's state).
#pragma once

#include <mpi.h>

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "polydem/broadphase/broad_phase.h"
#include "polydem/broadphase/cell_order.h"
#include "polydem/comm/particle_exchange.h"
#include "polydem/contact/contact.h"
#include "polydem/domain/block_forest.h"
#include "polydem/dynamics/contact_law.h"
#include "polydem/dynamics/contact_models.h"
#include "polydem/dynamics/integrator.h"
#include "polydem/dynamics/monitors.h"
#include "polydem/particles/contact_history.h"
#include "polydem/particles/material.h"
#include "polydem/particles/particle_storage.h"
#include "polydem/setup/setup.h"
#include "polydem/sim/bolts.h"
#include "polydem/sim/contact_phase.h"
#include "polydem/sim/force_operator.h"
#include "polydem/sim/ground_motion.h"
#include "polydem/sim/load_balancing.h"
#include "polydem/timeloop/time_loop.h"

namespace polydem::sim {

/// The two stages of a run (Keissar section 3.3, after 3DEC): an optional initial-equilibrium
/// stage with heavy damping and high friction, then the scene's own values.
enum class Stage { kEquilibrium, kMain };

/// Where a scene's shape sits in its body frame.
struct ShapeFrame {
  Quat rotation;  // body frame -> the frame the scene gave the shape in
  Vec3 centroid;  // in that frame
};

/// A user's force operator (sim/force_operator.h) under its name, which is also its timer's.
struct NamedForceOperator {
  std::string name;
  ForceOperator apply;
};

struct StepState {
  StepState(const setup::Setup& scene_in, MPI_Comm comm_in);

  /// The current stage's time (that of the positions) and time step.
  double time() const { return loop.time(); }
  double dt() const { return scene.dt; }
  /// Mass and principal inertia of local or ghost entry i.
  dynamics::MassProperties massProperties(std::size_t i) const {
    const auto& p = storage[i];
    const double density = densities[p.material];
    const auto& sh = shapes[p.shape];
    return {density * sh.volume, density * sh.principal_moments};
  }

  // --- the run ---------------------------------------------------------------------------------
  setup::Setup scene;
  MPI_Comm comm;
  int rank = 0, ranks = 1;
  Stage stage = Stage::kMain;
  /// The current stage's loop: step count, exact time, the operators and their timers.
  timeloop::TimeLoop loop;

  // --- built once from the setup (sim/simulation_setup.cpp) -----------------------------------
  particles::ShapeTable shapes;
  std::vector<ShapeFrame> shape_frames;
  particles::MaterialTable materials;
  std::vector<double> densities;
  std::vector<dynamics::LawCoefficients> law_main, law_equilibrium;
  // Joints: joint plane -> [[joint]] (-1: none), and coefficients per joint and material pair
  // (sim/pair_law.h PairJoints); empty for a scene without joints.
  std::vector<std::int32_t> plane_joint;
  std::vector<dynamics::LawCoefficients> joint_law_main, joint_law_equilibrium;
  Bolts bolts;                         // replicated on every rank (sim/bolts.h)
  std::optional<GroundMotion> ground;  // [seismic] record: moves the fixed particles
  std::unique_ptr<contact::Kernel> kernel;
  std::unique_ptr<broadphase::BroadPhase> broadphase;
  double ghost_range = 0.0;  // largest free circumradius + margin
  double r_free = 0.0;       // largest free circumradius
  double margin = 0.0;       // absolute contact margin
  dynamics::ContactModel contact_model = dynamics::ContactModel::kSubContacts;
  bool overlap_centroid = false;  // contact_point = "overlap-centroid"
  /// User force operators, in the order added (sim/force_operator.h).
  std::vector<NamedForceOperator> force_operators;
  /// Called after every step (checks, series, snapshots, checkpoints).
  std::vector<std::function<void()>> observers;

  // --- the particles and their decomposition --------------------------------------------------
  particles::ParticleStorage storage;
  particles::ContactHistory history;
  std::unique_ptr<domain::BlockForest> forest;
  comm::ParticleExchange exchange;

  // --- load balancing: the work of the contact phases, the decisions (sim/load_balancing.h) ---
  LoadBalancer balancer;

  // --- the step's work and statistics ---------------------------------------------------------
  ContactPhase contact_phase;
  ContactPhaseStats contact_stats;
  std::vector<dynamics::ForceAccumulator> forces;  // parallel to storage during a step only
  dynamics::ForceRatio ratio_local;  // this rank's share of Keissar eq. 3.2, last contact phase
  // The broad phase's input and output.
  std::vector<broadphase::CandidatePair> candidates;
  std::vector<Vec3> centers;
  std::vector<double> radii;
  std::vector<Uid> uids;
  std::vector<std::uint8_t> active;
  broadphase::CellOrder cell_order;
  std::int64_t sorts = 0;
  bool sort_started = false;  // sortParticles() ran at this object's first step
  // The exchange: the one in flight, and totals.
  bool exchange_in_flight = false;  // posted messages still travel (exchange -> exchange finish)
  comm::ExchangeStats exchange_stats;
  comm::ExchangeStats exchange_totals;
  comm::ExchangeStats step_exchange_totals;
  std::int64_t exchanges = 0;
  std::int64_t migrated_histories = 0;
  // The early contacts (step/early_contacts.cpp): work on the next step's pairs done while an
  // exchange is in flight. It is valid for the ghosts and particles that exchange delivers alone:
  // every exchange or ghost refresh (a change of state between steps refreshes the ghosts) counts
  // a new ghost epoch, and the contact phase takes early work of an older epoch for none.
  std::vector<broadphase::CandidatePair> early_candidates;
  std::uint64_t ghost_epoch = 0;
  std::uint64_t early_epoch = 0;  // the ghost epoch the early work was made in
  double early_seconds = 0.0;     // spent in the early contacts since the start

  // --- between steps --------------------------------------------------------------------------
  bool leapfrog_fresh = false;                    // started from the setup and not stepped since
  const std::string* running_operator = nullptr;  // the force operator being called, if any
};

}  // namespace polydem::sim
