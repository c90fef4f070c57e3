// Operator "integrate": the leapfrog for free particles (with the stage's local damping),
// prescribed motion for driven ones, the ground's motion for fixed ones under a [seismic] record
// (sim/ground_motion.h).
#include "polydem/dynamics/driver.h"
#include "polydem/dynamics/integrator.h"
#include "polydem/sim/step/operators.h"

namespace polydem::sim {

namespace {

// The fixed particles move with the ground of the [seismic] record (sim/ground_motion.h): by its
// exact displacement over the step, with its velocity at the half step, every rank alike.
void moveWithGround(StepState& s) {
  const Vec3 shift = s.ground->displacement(s.time() + s.dt()) - s.ground->displacement(s.time());
  const Vec3 velocity = s.ground->velocity(s.time() + 0.5 * s.dt());
  for (std::size_t i = 0; i < s.storage.localCount(); ++i) {
    auto& p = s.storage[i];
    if (!p.isFixed()) continue;
    p.position += shift;
    p.velocity = velocity;
  }
}

}  // namespace

void integrate(StepState& s) {
  s.leapfrog_fresh = false;
  if (s.ground && s.stage == Stage::kMain) moveWithGround(s);
  for (std::size_t i = 0; i < s.storage.localCount(); ++i) {
    auto& p = s.storage[i];
    if (p.isFree()) {
      const double alpha = s.stage == Stage::kEquilibrium ? s.scene.equilibrium.local_damping
                                                          : s.materials[p.material].local_damping;
      dynamics::advanceFree(p, s.massProperties(i), s.forces[i].force, s.forces[i].torque, s.dt(),
                            alpha);
    } else if (p.isDriven() && s.stage == Stage::kMain) {
      dynamics::advanceDriven(p, s.scene.drivers[p.driver], s.time(), s.dt());
    }
  }
}

}  // namespace polydem::sim
