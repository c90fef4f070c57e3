// Operator "derived": the particles' derived state (world vertices, rotations, inverse
// inertia) of owned and ghost particles, and the driven bodies' angular velocities.
#include "polydem/sim/step/operators.h"

#include "polydem/dynamics/driver.h"

namespace polydem::sim {

void updateDerived(StepState& s) {
  s.storage.updateDerived(s.shapes, s.densities);
  // Driven bodies turn with their driver's angular velocity, at the same half step as the
  // free particles' velocities (frozen during the equilibrium stage).
  const double t_half = s.time() - 0.5 * s.dt();
  for (std::size_t i = 0; i < s.storage.localCount(); ++i) {
    const auto& p = s.storage[i];
    if (!p.isDriven()) continue;
    const Vec3 w = s.stage == Stage::kEquilibrium
                       ? Vec3::Zero()
                       : dynamics::driverState(s.scene.drivers[p.driver], t_half).angular_velocity;
    s.storage.setAngularVelocity(i, w);
  }
}

}  // namespace polydem::sim
