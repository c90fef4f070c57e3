// Operator "water": the hydrostatic pressure of [water] on the joint faces of owned free
// particles (sim/water.h), at the stage's time (0 throughout the equilibrium stage).
#include <span>

#include "polydem/sim/step/operators.h"
#include "polydem/sim/water.h"

namespace polydem::sim {

void addWaterPressure(StepState& s) {
  if (!s.scene.water.enabled) return;
  addWaterForces(s.scene.water, s.stage == Stage::kEquilibrium ? 0.0 : s.time(), s.shapes,
                 s.storage,
                 std::span<dynamics::ForceAccumulator>(s.forces.data(), s.storage.localCount()));
}

}  // namespace polydem::sim
