// Operator "early contacts": while the exchange's messages travel, the local particles here are
// those of the next step minus the arrivals, at their next positions: their derived data, their
// pairs (no ghost yet, so every pair has two local members) and the contact phase's work on those
// pairs (sim/contact_phase.h runEarly). The next step's contact phase takes the results unless a
// ghost refresh (a change of state between steps) started a new ghost epoch since (step_state.h).
#include <chrono>

#include "polydem/sim/step/operators.h"

namespace polydem::sim {

void evaluateEarlyContacts(StepState& s) {
  if (!s.exchange_in_flight || !s.scene.domain.overlap_exchange) return;
  const auto t0 = std::chrono::steady_clock::now();
  updateDerived(s);
  findPairs(s, s.early_candidates);
  s.contact_phase.runEarly(contactSetup(s), s.storage, s.early_candidates, s.history);
  s.early_epoch = s.ghost_epoch;
  s.early_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace polydem::sim
