// Adding force operators to a Simulation (sim/force_operator.h).
#include <vector>

#include "polydem/core/error.h"
#include "polydem/core/strings.h"
#include "polydem/dynamics/integrator.h"
#include "polydem/sim/simulation.h"
#include "polydem/sim/step/operators.h"
#include "polydem/sim/step/step_list.h"

namespace polydem::sim {

void Simulation::requireBetweenSteps(std::string_view what) const {
  if (!state_.running_operator) return;
  throw Error(cat(what, " called from inside force operator '", *state_.running_operator,
                  "': the step that calls the operator is half done (forces summed, particles ",
                  "not moved); step, change or checkpoint the simulation between steps, after ",
                  "step() or run() has returned"));
}

void Simulation::addForceOperator(std::string name, ForceOperator op) {
  requireBetweenSteps("addForceOperator");
  if (name.empty()) throw Error("addForceOperator: a force operator needs a name");
  if (!op) throw Error(cat("addForceOperator: force operator '", name, "' is empty"));
  for (const auto& existing : state_.force_operators) {
    if (existing.name == name) {
      throw Error(cat("addForceOperator: a force operator named '", name, "' is already added"));
    }
  }
  if (isStepOperator(name)) {
    throw Error(cat("addForceOperator: '", name, "' is the name of an operator of the step; ",
                    "a force operator needs a name of its own (it is also its timer's)"));
  }
  if (state_.leapfrog_fresh) startLeapfrogWith(name, op);
  state_.force_operators.push_back({std::move(name), std::move(op)});
  // Into the step, after the operators added before it; during the equilibrium stage also into
  // the main stage's parked loop.
  const std::size_t k = state_.force_operators.size() - 1;
  addUserOperator(state_.loop, state_, k);
  if (auto* parked = stages_.parkedLoop()) addUserOperator(*parked, state_, k);
}

// The constructor started the leapfrog (velocities to t = -dt/2) with the forces it knew; an
// operator added before the first step gets its half kick too, as if it had been there (the
// start is linear in the forces). Its velocities are then those at -dt/2, not the scene's.
void Simulation::startLeapfrogWith(const std::string& name, const ForceOperator& op) {
  std::vector<dynamics::ForceAccumulator> extra(state_.storage.localCount());
  ForceStep step;
  step.time = 0.0;
  step.dt = dt();
  step.reach = stepReach();
  step.particles = &state_.storage;
  step.forces = extra;
  callForceOperator(state_, name, op, step);
  for (std::size_t i = 0; i < state_.storage.localCount(); ++i) {
    auto& p = state_.storage[i];
    if (p.isFree()) {
      dynamics::startLeapfrog(p, massProperties(i), extra[i].force, extra[i].torque, dt());
    }
  }
  refreshGhosts(state_);
}

std::vector<std::string> Simulation::forceOperatorNames() const {
  std::vector<std::string> names;
  for (const auto& op : state_.force_operators) names.push_back(op.name);
  return names;
}

}  // namespace polydem::sim
