// Operator "bolts": the [[bolt]]s' forces at the joints they cross, from the gathered poses of the
// bolted blocks; their state is replicated on every rank (sim/bolts.h). Collective.
#include <span>

#include "polydem/sim/step/operators.h"

namespace polydem::sim {

void addBoltForces(StepState& s) {
  if (s.bolts.empty()) return;
  s.bolts.addForces(s.storage,
                    std::span<dynamics::ForceAccumulator>(s.forces.data(), s.storage.localCount()),
                    s.stage == Stage::kEquilibrium ? 0.0 : s.time(), s.comm);
}

}  // namespace polydem::sim
