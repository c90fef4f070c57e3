// The stages of a run: the leapfrog's start, the initial-equilibrium stage and the main run.
#include "polydem/sim/simulation.h"

#include <chrono>
#include <cmath>

#include "polydem/core/error.h"
#include "polydem/core/exact_sum.h"
#include "polydem/core/logging.h"
#include "polydem/core/memory.h"
#include "polydem/core/mpi_env.h"
#include "polydem/core/state_hash.h"
#include "polydem/core/strings.h"
#include "polydem/domain/partition.h"
#include "polydem/domain/rebalance.h"
#include "polydem/dynamics/driver.h"
#include "polydem/dynamics/integrator.h"
#include "polydem/sim/pair_memory.h"
#include "polydem/sim/seismic.h"
#include "polydem/sim/water.h"

namespace polydem::sim {

void Simulation::startLeapfrog() {
  // Velocities of a scene are given at t = 0; the leapfrog keeps them at t - dt/2. The forces at
  // t = 0 are computed on a copy of the (empty) history and bolt state so that this start leaves
  // no trace.
  const particles::ContactHistory saved = history_;
  const auto saved_bolts = bolts_.states();
  updateDerived();
  findCandidates();
  computeContacts();
  history_ = saved;
  bolts_.restore(saved_bolts);
  for (std::size_t i = 0; i < storage_.localCount(); ++i) {
    auto& p = storage_[i];
    if (p.isFree()) {
      dynamics::startLeapfrog(p, massProperties(i), forces_[i].force, forces_[i].torque, dt());
    }
  }
  refreshGhosts();
  leapfrog_fresh_ = true;
}

void Simulation::step() {
  requireBetweenSteps("step");
  loop_.singleStep();
}

// The equilibrium stage runs in its own loop, with the same steps; the main stage's loop is parked
// meanwhile.
void Simulation::enterEquilibrium() {
  std::swap(parked_loop_, loop_);
  loop_ = timeloop::TimeLoop(comm_);
  registerSteps();
  loop_.stopWhenForceRatioBelow(scene_.equilibrium.force_ratio,
                                [this] { return monitors().force_ratio; });
  loop_.stopAtStep(scene_.equilibrium.max_steps);
  stage_ = Stage::kEquilibrium;
}

std::int64_t Simulation::runEquilibrium() {
  requireBetweenSteps("runEquilibrium");
  if (!scene_.equilibrium.enabled || equilibrium_done_) return equilibrium_steps_;
  if (stage_ != Stage::kEquilibrium) enterEquilibrium();
  log::info(cat("initial equilibrium: local damping ", scene_.equilibrium.local_damping,
                ", friction ", scene_.equilibrium.friction_angle, " deg, until R < ",
                scene_.equilibrium.force_ratio));
  const auto reason = loop_.run();
  equilibrium_steps_ = loop_.step();
  if (reason == timeloop::StopReason::kUserCondition) return equilibrium_steps_;  // interrupted
  equilibrium_reached_ = reason == timeloop::StopReason::kForceRatio;
  log::info(cat("initial equilibrium ", equilibrium_reached_ ? "reached" : "NOT reached", " after ",
                equilibrium_steps_, " steps (", loop_.stopMessage(), ")"));
  equilibrium_timing_ = loop_.timing();
  std::swap(parked_loop_, loop_);
  stage_ = Stage::kMain;
  equilibrium_done_ = true;
  if (scene_.equilibrium.reset_velocities) {
    for (std::size_t i = 0; i < storage_.localCount(); ++i) {
      auto& p = storage_[i];
      if (!p.isFree()) continue;
      p.velocity.setZero();
      p.angular_momentum.setZero();
    }
    refreshGhosts();
  }
  return equilibrium_steps_;
}

void requireStopCondition(const setup::Setup& scene) {
  // The scene reader requires one; a scene changed from Python may have neither, and the loop's
  // own stop condition (the step hook) would then never hold.
  if (!scene.end_time && !scene.steps) {
    throw Error(cat("scene ", scene.file, ": neither end_time nor steps is set: nothing would ",
                    "stop the run"));
  }
}

timeloop::StopReason Simulation::run() {
  requireBetweenSteps("run");
  requireStopCondition(scene_);
  if (scene_.end_time) loop_.stopAtTime(*scene_.end_time);
  if (scene_.steps) loop_.stopAtStep(*scene_.steps);
  return loop_.run();
}

}  // namespace polydem::sim
