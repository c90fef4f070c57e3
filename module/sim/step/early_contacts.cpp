// Early contacts: the next contact phase's pairs of two local particles, while the exchange is in flight.
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

// The local particles here now are those of the next step minus the arrivals, at their next
// positions: their derived data, their pairs (no ghost yet, so every pair has two local members)
// and the contact phase's work on those pairs. The next step's contact phase takes the results
// unless the state changed in between (every change between steps refreshes the ghosts, and
// refreshGhosts() forgets them).
void Simulation::evaluateEarly() {
  const auto t0 = std::chrono::steady_clock::now();
  updateDerived();
  findPairs(early_candidates_);
  contact_phase_.runEarly(contactSetup(), storage_, early_candidates_, history_);
  early_seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace polydem::sim
