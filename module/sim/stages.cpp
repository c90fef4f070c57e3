// The stages of a run (stages.h): the leapfrog's start, the initial-equilibrium stage and the main
// run, each a loop over the step of sim/step/step_list.cpp.
#include "polydem/sim/stages.h"

#include <utility>

#include "polydem/core/error.h"
#include "polydem/core/logging.h"
#include "polydem/core/strings.h"
#include "polydem/dynamics/integrator.h"
#include "polydem/sim/global_monitors.h"
#include "polydem/sim/step/operators.h"
#include "polydem/sim/step/step_list.h"

namespace polydem::sim {

void Stages::registerSteps() {
  s_.loop.setTimeStep(s_.scene.dt);
  addStep(s_.loop, s_);
  s_.loop.stopWhen("interruption requested", [this] { return step_hook_ && step_hook_(); });
  s_.loop.setMonitor([this] {
    const auto m = globalMonitors(s_);
    return timeloop::Monitor{m.contacts, m.kinetic_energy, m.force_ratio};
  });
}

void Stages::startLeapfrog() {
  // The forces at t = 0 are computed on a copy of the (empty) history and bolt state so that
  // this start leaves no trace.
  const particles::ContactHistory saved = s_.history;
  const auto saved_bolts = s_.bolts.states();
  computeForces(s_);
  s_.history = saved;
  s_.bolts.restore(saved_bolts);
  for (std::size_t i = 0; i < s_.storage.localCount(); ++i) {
    auto& p = s_.storage[i];
    if (p.isFree()) {
      dynamics::startLeapfrog(p, s_.massProperties(i), s_.forces[i].force, s_.forces[i].torque,
                              s_.dt());
    }
  }
  refreshGhosts(s_);
  s_.leapfrog_fresh = true;
}

// The equilibrium stage runs in its own loop, with the same steps; the main stage's loop is parked
// meanwhile.
void Stages::enterEquilibrium() {
  std::swap(parked_loop_, s_.loop);
  s_.loop = timeloop::TimeLoop(s_.comm);
  registerSteps();
  s_.loop.stopWhenForceRatioBelow(s_.scene.equilibrium.force_ratio,
                                  [this] { return globalForceRatio(s_); });
  s_.loop.stopAtStep(s_.scene.equilibrium.max_steps);
  s_.stage = Stage::kEquilibrium;
}

// Back to the main stage's loop; the scene may ask for the blocks to start it at rest.
void Stages::leaveEquilibrium() {
  equilibrium_timing_ = s_.loop.timing();
  std::swap(parked_loop_, s_.loop);
  s_.stage = Stage::kMain;
  equilibrium_done_ = true;
  if (!s_.scene.equilibrium.reset_velocities) return;
  for (std::size_t i = 0; i < s_.storage.localCount(); ++i) {
    auto& p = s_.storage[i];
    if (!p.isFree()) continue;
    p.velocity.setZero();
    p.angular_momentum.setZero();
  }
  refreshGhosts(s_);
}

std::int64_t Stages::runEquilibrium() {
  const auto& eq = s_.scene.equilibrium;
  if (!eq.enabled || equilibrium_done_) return equilibrium_steps_;
  if (s_.stage != Stage::kEquilibrium) enterEquilibrium();
  log::info(cat("initial equilibrium: local damping ", eq.local_damping, ", friction ",
                eq.friction_angle, " deg, until R < ", eq.force_ratio));
  const auto reason = s_.loop.run();
  equilibrium_steps_ = s_.loop.step();
  if (reason == timeloop::StopReason::kUserCondition) return equilibrium_steps_;  // interrupted
  equilibrium_reached_ = reason == timeloop::StopReason::kForceRatio;
  log::info(cat("initial equilibrium ", equilibrium_reached_ ? "reached" : "NOT reached", " after ",
                equilibrium_steps_, " steps (", s_.loop.stopMessage(), ")"));
  leaveEquilibrium();
  return equilibrium_steps_;
}

timeloop::StopReason Stages::run() {
  if (s_.scene.end_time) s_.loop.stopAtTime(*s_.scene.end_time);
  if (s_.scene.steps) s_.loop.stopAtStep(*s_.scene.steps);
  return s_.loop.run();
}

void Stages::restore(std::int64_t equilibrium_steps, bool reached, bool in_equilibrium) {
  equilibrium_steps_ = equilibrium_steps;
  equilibrium_reached_ = reached;
  if (in_equilibrium) {
    enterEquilibrium();
  } else {
    equilibrium_done_ = true;
  }
}

}  // namespace polydem::sim
