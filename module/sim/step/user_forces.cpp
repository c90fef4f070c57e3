// A user's force operator as an operator of the step (sim/force_operator.h): each one added with
// Simulation::addForceOperator runs under its own name and timer, after the scene's forces and
// before the force ratio, in the order added (step_list.cpp).
#include <span>

#include "polydem/sim/step/operators.h"

namespace polydem::sim {

void applyForceOperator(StepState& s, const NamedForceOperator& op) {
  ForceStep step;
  step.time = s.stage == Stage::kEquilibrium ? 0.0 : s.time();
  step.dt = s.dt();
  step.equilibrium = s.stage == Stage::kEquilibrium;
  step.reach = s.ghost_range;
  step.particles = &s.storage;
  step.forces = std::span<dynamics::ForceAccumulator>(s.forces.data(), s.storage.localCount());
  callForceOperator(s, op.name, op.apply, step);
}

void callForceOperator(StepState& s, const std::string& name, const ForceOperator& op,
                       const ForceStep& step) {
  s.running_operator = &name;
  try {
    op(step);
  } catch (...) {
    s.running_operator = nullptr;
    throw;
  }
  s.running_operator = nullptr;
}

}  // namespace polydem::sim
