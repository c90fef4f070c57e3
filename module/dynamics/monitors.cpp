#include "polydem/dynamics/monitors.h"

namespace polydem::dynamics {

double kineticEnergy(const particles::Particle& p, const MassProperties& mass) {
  if (!p.isFree()) return 0.0;
  const Vec3 w = angularVelocity(p.orientation, p.angular_momentum, mass.principal_inertia);
  return kineticEnergy(mass.mass, p.velocity, p.angular_momentum, w);
}

double ForceRatio::value() const {
  const double applied = applied_.value();
  return applied > 0.0 ? unbalanced_.value() / applied : 0.0;
}

}  // namespace polydem::dynamics
