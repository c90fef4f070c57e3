// Observers: checks, series, snapshots and checkpoints after each step.
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

void Simulation::observe() {
  for (const auto& o : observers_) o();
}

}  // namespace polydem::sim
