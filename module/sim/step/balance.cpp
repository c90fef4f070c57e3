// Operator "balance": every domain.rebalance_every steps, a new decomposition is weighed by the
// work of the last contact phase (sim/load_balancing.h) before the particles move, so that one
// exchange takes them to their new owners (and their ghosts to the new neighbours).
#include "polydem/sim/load_balancing.h"
#include "polydem/sim/step/operators.h"

namespace polydem::sim {

void balanceWhenDue(StepState& s) {
  const std::int64_t next_step = s.loop.step() + 1;
  if (s.scene.domain.rebalance_every > 0 && next_step % s.scene.domain.rebalance_every == 0) {
    s.balancer.adopt(s);
  }
}

}  // namespace polydem::sim
