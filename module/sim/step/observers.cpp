// Operator "observers": after every step, once the loop counts it (step and time advanced), the
// functions added with Simulation::addObserver: checks, series, snapshots, checkpoints (module
// run), each deciding itself whether it is due.
#include "polydem/sim/step/operators.h"

namespace polydem::sim {

void observe(StepState& s) {
  for (const auto& o : s.observers) o();
}

}  // namespace polydem::sim
