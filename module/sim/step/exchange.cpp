// Operator "exchange": migration of the particles that left their rank's blocks, with their pair
// histories, and the ghost refresh (comm/particle_exchange.h). Its messages are posted by
// "exchange" and received by "exchange finish"; the early contacts run in between.
#include "polydem/sim/step/operators.h"

namespace polydem::sim {

void postExchange(StepState& s) {
  const std::int64_t next_step = s.loop.step() + 1;
  // A new ghost epoch: the early contacts now made are for the state this exchange delivers.
  ++s.ghost_epoch;
  s.exchange_in_flight =
      s.exchange.post(*s.forest, s.storage, s.history, s.shapes, s.ghost_range, next_step);
}

void finishExchange(StepState& s) {
  s.exchange_in_flight = false;
  s.exchange_stats = s.exchange.finish(*s.forest, s.storage, s.history);
  s.migrated_histories += s.exchange_stats.histories_received;
  s.exchange_totals += s.exchange_stats;
  s.step_exchange_totals += s.exchange_stats;
  ++s.exchanges;
}

void refreshGhosts(StepState& s) {
  ++s.ghost_epoch;
  s.exchange_stats = s.exchange.refreshGhosts(*s.forest, s.storage, s.shapes, s.ghost_range);
}

}  // namespace polydem::sim
