// The stages of a run: the leapfrog's start, the initial-equilibrium stage and the main run, each a
// loop over the step of sim/step/step_list.cpp.
#include "polydem/sim/simulation.h"

#include <utility>

#include "polydem/core/error.h"
#include "polydem/core/logging.h"
#include "polydem/core/strings.h"
#include "polydem/dynamics/integrator.h"
#include "polydem/sim/step/operators.h"
#include "polydem/sim/step/step_list.h"

namespace polydem::sim {

// The loop's steps: the operators of the step (sim/step/step_list.cpp), the step hook as a stop
// condition, the global monitors for the progress line.
void Simulation::registerSteps() {
  state_.loop.setTimeStep(state_.scene.dt);
  addStep(state_.loop, state_);
  state_.loop.stopWhen("interruption requested", [this] { return step_hook_ && step_hook_(); });
  state_.loop.setMonitor([this] {
    const auto m = monitors();
    return timeloop::Monitor{m.contacts, m.kinetic_energy, m.force_ratio};
  });
}

void Simulation::startLeapfrog() {
  // Velocities of a scene are given at t = 0; the leapfrog keeps them at t - dt/2. The forces at
  // t = 0 are computed on a copy of the (empty) history and bolt state so that this start leaves
  // no trace.
  const particles::ContactHistory saved = state_.history;
  const auto saved_bolts = state_.bolts.states();
  computeForces(state_);
  state_.history = saved;
  state_.bolts.restore(saved_bolts);
  for (std::size_t i = 0; i < state_.storage.localCount(); ++i) {
    auto& p = state_.storage[i];
    if (p.isFree()) {
      dynamics::startLeapfrog(p, massProperties(i), state_.forces[i].force, state_.forces[i].torque,
                              dt());
    }
  }
  refreshGhosts(state_);
  state_.leapfrog_fresh = true;
}

void Simulation::step() {
  requireBetweenSteps("step");
  state_.loop.singleStep();
}

// The equilibrium stage runs in its own loop, with the same steps; the main stage's loop is parked
// meanwhile.
void Simulation::enterEquilibrium() {
  std::swap(parked_loop_, state_.loop);
  state_.loop = timeloop::TimeLoop(state_.comm);
  registerSteps();
  state_.loop.stopWhenForceRatioBelow(state_.scene.equilibrium.force_ratio,
                                      [this] { return monitors().force_ratio; });
  state_.loop.stopAtStep(state_.scene.equilibrium.max_steps);
  state_.stage = Stage::kEquilibrium;
}

std::int64_t Simulation::runEquilibrium() {
  requireBetweenSteps("runEquilibrium");
  if (!state_.scene.equilibrium.enabled || equilibrium_done_) return equilibrium_steps_;
  if (state_.stage != Stage::kEquilibrium) enterEquilibrium();
  log::info(cat("initial equilibrium: local damping ", state_.scene.equilibrium.local_damping,
                ", friction ", state_.scene.equilibrium.friction_angle, " deg, until R < ",
                state_.scene.equilibrium.force_ratio));
  const auto reason = state_.loop.run();
  equilibrium_steps_ = state_.loop.step();
  if (reason == timeloop::StopReason::kUserCondition) return equilibrium_steps_;  // interrupted
  equilibrium_reached_ = reason == timeloop::StopReason::kForceRatio;
  log::info(cat("initial equilibrium ", equilibrium_reached_ ? "reached" : "NOT reached", " after ",
                equilibrium_steps_, " steps (", state_.loop.stopMessage(), ")"));
  equilibrium_timing_ = state_.loop.timing();
  std::swap(parked_loop_, state_.loop);
  state_.stage = Stage::kMain;
  equilibrium_done_ = true;
  if (state_.scene.equilibrium.reset_velocities) {
    for (std::size_t i = 0; i < state_.storage.localCount(); ++i) {
      auto& p = state_.storage[i];
      if (!p.isFree()) continue;
      p.velocity.setZero();
      p.angular_momentum.setZero();
    }
    refreshGhosts(state_);
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
  requireStopCondition(state_.scene);
  if (state_.scene.end_time) state_.loop.stopAtTime(*state_.scene.end_time);
  if (state_.scene.steps) state_.loop.stopAtStep(*state_.scene.steps);
  return state_.loop.run();
}

}  // namespace polydem::sim
