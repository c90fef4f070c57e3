// Adding force operators to a Simulation (sim/force_operator.h).
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

void Simulation::requireBetweenSteps(std::string_view what) const {
  if (!running_operator_) return;
  throw Error(cat(what, " called from inside force operator '", *running_operator_,
                  "': the step that calls the operator is half done (forces summed, particles ",
                  "not moved); step, change or checkpoint the simulation between steps, after ",
                  "step() or run() has returned"));
}

void Simulation::addForceOperator(std::string name, ForceOperator op) {
  requireBetweenSteps("addForceOperator");
  if (name.empty()) throw Error("addForceOperator: a force operator needs a name");
  if (!op) throw Error(cat("addForceOperator: force operator '", name, "' is empty"));
  for (const auto& existing : force_operators_) {
    if (existing.name == name) {
      throw Error(cat("addForceOperator: a force operator named '", name, "' is already added"));
    }
  }
  if (leapfrog_fresh_) startLeapfrogWith(name, op);
  force_operators_.push_back({std::move(name), std::move(op)});
}

// The constructor started the leapfrog (velocities to t = -dt/2) with the forces it knew; an
// operator added before the first step gets its half kick too, as if it had been there (the
// start is linear in the forces). Its velocities are then those at -dt/2, not the scene's.
void Simulation::startLeapfrogWith(const std::string& name, const ForceOperator& op) {
  std::vector<dynamics::ForceAccumulator> extra(storage_.localCount());
  ForceStep step;
  step.time = 0.0;
  step.dt = dt();
  step.particles = &storage_;
  step.forces = extra;
  callForceOperator(name, op, step);
  for (std::size_t i = 0; i < storage_.localCount(); ++i) {
    auto& p = storage_[i];
    if (p.isFree()) {
      dynamics::startLeapfrog(p, massProperties(i), extra[i].force, extra[i].torque, dt());
    }
  }
  refreshGhosts();
}

std::vector<std::string> Simulation::forceOperatorNames() const {
  std::vector<std::string> names;
  for (const auto& op : force_operators_) names.push_back(op.name);
  return names;
}

}  // namespace polydem::sim
