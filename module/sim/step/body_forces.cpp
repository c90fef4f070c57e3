// Operator "body forces": m g on every owned free particle, plus m g (kh h + kv z) of the
// pseudo-static earthquake load when the scene has [seismic] (sim/seismic.h).
#include "polydem/sim/seismic.h"
#include "polydem/sim/step/operators.h"

namespace polydem::sim {

void addBodyForces(StepState& s) {
  const Vec3 body = bodyAcceleration(s.scene);
  for (std::size_t i = 0; i < s.storage.localCount(); ++i) {
    if (s.storage[i].isFree()) s.forces[i].addBodyForce(s.storage.mass(i) * body);
  }
}

}  // namespace polydem::sim
