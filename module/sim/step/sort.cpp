// Sort: the local particles into the broad phase's cell order now and then.
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

// Particles sit in storage in creation and arrival order, and the broad phase's grids visit them
// in cell order: past the caches, every gather of a particle and every pair of the contact phase
// waits on memory. At the first step of this Simulation (and of a restart) and every sort_every
// steps, the local particles are put in the cell order of the grid of the smallest free particles
// (broadphase/cell_order.h; for one size, exactly the order the multilevel grid gathers them in).
// Ghosts keep their places. No result changes (contact_phase.h: uid order throughout).
void Simulation::sortParticles() {
  const std::int64_t every = scene_.domain.sort_every;
  if (every <= 0 || (sort_started_ && loop_.step() % every != 0)) return;
  sort_started_ = true;
  const double r_max = fillSphereSet();
  double r_min = r_max;
  bool any_free = false;
  for (std::size_t i = 0; i < storage_.localCount(); ++i) {
    if (!active_[i]) continue;
    any_free = true;
    r_min = std::min(r_min, radii_[i]);
  }
  if (!any_free) return;
  // The reach findCandidates() gives the grid of particles of this size (cell_factor 1).
  const double reach = 2.0 * r_min + margin_ + 1e-9 * 2.0 * r_max;
  storage_.permuteLocals(
      cell_order_.order({centers_, radii_, uids_, active_}, storage_.localCount(), reach));
  ++sorts_;
}

}  // namespace polydem::sim
