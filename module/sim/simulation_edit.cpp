// Changes of a running simulation's state between steps, made by a driving program (Python):
// they act on what a step reads and a checkpoint stores, so a run changed this way continues
// with the same bits on any rank count and after a restart.
#include "polydem/core/mpi_env.h"
#include "polydem/dynamics/integrator.h"
#include "polydem/sim/simulation.h"

namespace polydem::sim {

bool Simulation::setVelocity(Uid uid, const std::optional<Vec3>& velocity,
                             const std::optional<Vec3>& angular_velocity) {
  bool owned = false;
  for (std::size_t i = 0; i < storage_.localCount(); ++i) {
    auto& p = storage_[i];
    if (p.uid != uid || !p.isFree()) continue;
    if (velocity) p.velocity = *velocity;
    // The leapfrog keeps the angular momentum; L = R I R^T w at the current orientation.
    if (angular_velocity) {
      p.angular_momentum = dynamics::angularMomentum(p.orientation, *angular_velocity,
                                                     massProperties(i).principal_inertia);
    }
    owned = true;
  }
  // Ghost copies carry velocities into the contact law's damping: refresh them (collective).
  refreshGhosts();
  return mpi::allreduceOr(owned, comm_);
}

}  // namespace polydem::sim
