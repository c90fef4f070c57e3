// Derived state: world vertices, rotations and the driven bodies' angular velocities.
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

void Simulation::updateDerived() {
  storage_.updateDerived(shapes_, densities_);
  // Driven bodies turn with their driver's angular velocity, at the same half step as the
  // free particles' velocities (frozen during the equilibrium stage).
  const double t_half = time() - 0.5 * dt();
  for (std::size_t i = 0; i < storage_.localCount(); ++i) {
    const auto& p = storage_[i];
    if (!p.isDriven()) continue;
    const Vec3 w = stage_ == Stage::kEquilibrium
                       ? Vec3::Zero()
                       : dynamics::driverState(scene_.drivers[p.driver], t_half).angular_velocity;
    storage_.setAngularVelocity(i, w);
  }
}

}  // namespace polydem::sim
