// User force operators within the step (sim/force_operator.h).
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

void Simulation::applyForceOperators() {
  if (force_operators_.empty()) return;
  ForceStep step;
  step.time = stage_ == Stage::kEquilibrium ? 0.0 : time();
  step.dt = dt();
  step.equilibrium = stage_ == Stage::kEquilibrium;
  step.particles = &storage_;
  step.forces = std::span<dynamics::ForceAccumulator>(forces_.data(), storage_.localCount());
  for (const auto& op : force_operators_) callForceOperator(op.name, op.apply, step);
}

void Simulation::callForceOperator(const std::string& name, const ForceOperator& op,
                                   const ForceStep& step) {
  running_operator_ = &name;
  try {
    op(step);
  } catch (...) {
    running_operator_ = nullptr;
    throw;
  }
  running_operator_ = nullptr;
}

}  // namespace polydem::sim
