// The step: its operators in the order they run, registered with the loop.
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

void Simulation::registerSteps() {
  loop_.setTimeStep(scene_.dt);
  loop_.add("sort", [this] { sortParticles(); });  // storage order (no result changes)
  loop_.add("derived", [this] { updateDerived(); });
  loop_.add("broadphase", [this] { findCandidates(); });
  loop_.add("contacts", [this] { computeContacts(); });
  loop_.add("integrate", [this] { integrate(); });
  loop_.add("communicate", [this] { communicate(); });
  loop_.addObserver("observe", [this] { observe(); });  // after step and time count the step
  loop_.stopWhen("interruption requested", [this] { return step_hook_ && step_hook_(); });
  loop_.setMonitor([this] {
    const auto m = monitors();
    return timeloop::Monitor{m.contacts, m.kinetic_energy, m.force_ratio};
  });
}

}  // namespace polydem::sim
