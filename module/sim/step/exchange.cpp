// Exchange: domain check, rebalancing when due, migration and ghosts.
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

// A particle whose state is no longer finite, or that left the domain, ends the run with the
// scene file and the particle's line in the message (the exchange below would stop it too, but
// knows nothing of the scene).
void Simulation::checkParticlesInside(std::int64_t step) const {
  const auto& box = forest_->domain();
  for (std::size_t i = 0; i < storage_.localCount(); ++i) {
    const auto& p = storage_[i];
    if (!p.isFree()) continue;
    const bool finite = p.position.allFinite() && p.velocity.allFinite() &&
                        p.angular_momentum.allFinite() && p.orientation.coeffs().allFinite();
    if (finite && forest_->blockOf(forest_->wrap(p.position)) >= 0) continue;
    const std::string where = p.uid >= 1 && p.uid <= scene_.particles.size()
                                  ? cat(scene_.file, ":", scene_.particles[p.uid - 1].line, ": ")
                                  : cat(scene_.file, ": ");
    if (!finite) {
      throw SimulationError(cat(where, "particle ", p.uid, " has a state that is no longer finite ",
                                "at step ", step, " (position (", p.position.transpose(),
                                "), velocity (", p.velocity.transpose(), ")): forces or ",
                                "velocities overflowed; check gravity, densities, stiffnesses and ",
                                "dt in the scene"));
    }
    throw SimulationError(cat(where, "particle ", p.uid, " left the domain at (", p.position.x(),
                              ", ", p.position.y(), ", ", p.position.z(), ") at step ", step,
                              "; the domain is [", box.lo.x(), ", ", box.hi.x(), "] x [",
                              box.lo.y(), ", ", box.hi.y(), "] x [", box.lo.z(), ", ", box.hi.z(),
                              "]: enlarge [domain] min/max in the scene"));
  }
}

void Simulation::communicate() {
  const std::int64_t next_step = loop_.step() + 1;
  checkParticlesInside(next_step);
  // A new decomposition is weighed before the particles move, so that one exchange takes them to
  // their new owners (and their ghosts to the new neighbours).
  if (scene_.domain.rebalance_every > 0 && next_step % scene_.domain.rebalance_every == 0) {
    balanceDecomposition();
  }
  // While the messages travel, the next step's pairs of two local particles (sim/contact_phase.h).
  const bool in_flight =
      exchange_.post(*forest_, storage_, history_, shapes_, ghost_range_, next_step);
  if (in_flight && scene_.domain.overlap_exchange) evaluateEarly();
  exchange_stats_ = exchange_.finish(*forest_, storage_, history_);
  migrated_histories_ += exchange_stats_.histories_received;
  exchange_totals_ += exchange_stats_;
  step_exchange_totals_ += exchange_stats_;
  ++exchanges_;
}

void Simulation::refreshGhosts() {
  contact_phase_.discardEarly();
  exchange_stats_ = exchange_.refreshGhosts(*forest_, storage_, shapes_, ghost_range_);
}

}  // namespace polydem::sim
