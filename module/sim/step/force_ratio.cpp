// Operator "force ratio": this rank's sums of the force ratio (Keissar eq. 3.2) over the forces
// of its free particles, once every force of the step is in; Simulation::monitors() reduces them.
#include "polydem/sim/step/operators.h"

namespace polydem::sim {

void sumForceRatio(StepState& s) {
  s.ratio_local.clear();
  for (std::size_t i = 0; i < s.storage.localCount(); ++i) {
    if (s.storage[i].isFree()) s.ratio_local.add(s.forces[i]);
  }
}

}  // namespace polydem::sim
