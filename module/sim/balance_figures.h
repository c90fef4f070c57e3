// Per-rank figures of a run's balance and communication, reduced to min / mean / max over the
// ranks. Apart from the times, they are counts that do not depend on timing (the decomposition is
// a deterministic function of the state), so they can be checked on oversubscribed ranks.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>

#include "polydem/sim/simulation.h"

namespace polydem::sim {

struct Spread {
  double min = 0.0, mean = 0.0, max = 0.0;
  /// max / mean: 1 is perfect balance (1 as well when there is nothing to balance).
  double ratio() const { return mean > 0 ? max / mean : 1.0; }
};

struct BalanceFigures {
  int ranks = 1;
  domain::Index3 blocks{1, 1, 1};
  // The state after the last step, per rank.
  Spread owned;              // free particles owned
  Spread ghosts;             // ghost copies held
  Spread candidate_pairs;    // broad-phase pairs of the last contact phase
  Spread evaluated_pairs;    // kernel calls of the last contact phase (pairs across a border on
                             // both ranks)
  Spread early_pairs;        // of the evaluated pairs: those evaluated while the exchange before
                             // the step was in flight (sim/contact_phase.h)
  Spread contacts;           // touching pairs among them
  Spread work;               // the load model's cost of the last step (sim/load_balance.h)
  double unique_work = 0.0;  // the same work done once (as on one rank), summed over the ranks
  Spread bytes_last_step, messages_last_step;  // sent by the last step's exchange
  // Means per step over the steps run so far (since the start or the restart; the exchanges of
  // the start and of rebalancing left out).
  Spread bytes_per_step, messages_per_step;
  // Seconds per step in the exchange: waiting for the slowest rank, moving the bytes, and the rest
  // (finding destinations, packing, unpacking). Timings: not deterministic.
  Spread wait_seconds, transfer_seconds, bookkeeping_seconds;
  // Seconds per step of contact work done while the exchange was in flight (not part of the
  // three above; the loop's "early contacts" timer).
  Spread early_seconds;
};

/// The efficiency the balance and the duplicated border pairs allow, communication left out:
/// the work done once over ranks times the busiest rank's work (1 on one rank). A count, not a
/// time: the same on any machine.
double modelledEfficiency(const BalanceFigures& f);

/// Collective: every rank gets the same figures.
BalanceFigures balanceFigures(const Simulation& sim);

/// {"min", "mean", "max", "max_over_mean"}.
nlohmann::json toJson(const Spread& s);
/// The deterministic figures under "balance", the times under "communication_seconds_per_step".
nlohmann::json toJson(const BalanceFigures& f);

}  // namespace polydem::sim
