// Integrate: leapfrog for free particles, prescribed motion for driven and fixed ones.
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

void Simulation::integrate() {
  leapfrog_fresh_ = false;
  if (ground_ && stage_ == Stage::kMain) moveWithGround();
  for (std::size_t i = 0; i < storage_.localCount(); ++i) {
    auto& p = storage_[i];
    if (p.isFree()) {
      const double alpha = stage_ == Stage::kEquilibrium ? scene_.equilibrium.local_damping
                                                         : materials_[p.material].local_damping;
      dynamics::advanceFree(p, massProperties(i), forces_[i].force, forces_[i].torque, dt(), alpha);
    } else if (p.isDriven() && stage_ == Stage::kMain) {
      dynamics::advanceDriven(p, scene_.drivers[p.driver], time(), dt());
    }
  }
}

// The fixed particles move with the ground of the [seismic] record (sim/ground_motion.h): by its
// exact displacement over the step, with its velocity at the half step, every rank alike.
void Simulation::moveWithGround() {
  const Vec3 shift = ground_->displacement(time() + dt()) - ground_->displacement(time());
  const Vec3 velocity = ground_->velocity(time() + 0.5 * dt());
  for (std::size_t i = 0; i < storage_.localCount(); ++i) {
    auto& p = storage_[i];
    if (!p.isFixed()) continue;
    p.position += shift;
    p.velocity = velocity;
  }
}

}  // namespace polydem::sim
