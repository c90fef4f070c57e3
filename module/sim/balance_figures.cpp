#include "polydem/sim/balance_figures.h"

#include <mpi.h>

#include <algorithm>
#include <array>

#include "polydem/core/mpi_env.h"

namespace polydem::sim {

BalanceFigures balanceFigures(const Simulation& sim) {
  const auto& p = sim.particles();
  std::int64_t owned = 0;
  for (std::size_t i = 0; i < p.localCount(); ++i) owned += p[i].isFree();
  const auto& c = sim.contactStats();
  const auto& last = sim.exchangeStats();
  const auto& total = sim.stepExchangeTotals();
  const double steps = static_cast<double>(std::max<std::int64_t>(1, sim.exchanges()));
  const double bookkeeping = total.seconds - total.wait_seconds - total.transfer_seconds;
  constexpr int kFigures = 16;
  const std::array<double, kFigures> mine = {static_cast<double>(owned),
                                             static_cast<double>(p.ghostCount()),
                                             static_cast<double>(c.candidates),
                                             static_cast<double>(c.evaluated),
                                             static_cast<double>(c.touching),
                                             sim.lastWork().done,
                                             static_cast<double>(last.bytes_sent),
                                             static_cast<double>(last.messages_sent),
                                             static_cast<double>(total.bytes_sent) / steps,
                                             static_cast<double>(total.messages_sent) / steps,
                                             total.wait_seconds / steps,
                                             total.transfer_seconds / steps,
                                             bookkeeping / steps,
                                             static_cast<double>(c.early),
                                             sim.earlySeconds() / steps,
                                             sim.lastWork().unique};
  std::array<double, kFigures> lo{}, hi{}, sum{};
  MPI_Allreduce(mine.data(), lo.data(), kFigures, MPI_DOUBLE, MPI_MIN, sim.comm());
  MPI_Allreduce(mine.data(), hi.data(), kFigures, MPI_DOUBLE, MPI_MAX, sim.comm());
  MPI_Allreduce(mine.data(), sum.data(), kFigures, MPI_DOUBLE, MPI_SUM, sim.comm());
  BalanceFigures f;
  f.ranks = mpi::size(sim.comm());
  f.blocks = sim.forest().counts();
  Spread unique;
  Spread* out[kFigures] = {&f.owned,
                           &f.ghosts,
                           &f.candidate_pairs,
                           &f.evaluated_pairs,
                           &f.contacts,
                           &f.work,
                           &f.bytes_last_step,
                           &f.messages_last_step,
                           &f.bytes_per_step,
                           &f.messages_per_step,
                           &f.wait_seconds,
                           &f.transfer_seconds,
                           &f.bookkeeping_seconds,
                           &f.early_pairs,
                           &f.early_seconds,
                           &unique};
  for (int k = 0; k < kFigures; ++k) *out[k] = {lo[k], sum[k] / f.ranks, hi[k]};
  f.unique_work = sum[kFigures - 1];
  return f;
}

double modelledEfficiency(const BalanceFigures& f) {
  return f.work.max > 0 ? f.unique_work / (f.ranks * f.work.max) : 1.0;
}

nlohmann::json toJson(const Spread& s) {
  return {{"min", s.min}, {"mean", s.mean}, {"max", s.max}, {"max_over_mean", s.ratio()}};
}

nlohmann::json toJson(const BalanceFigures& f) {
  using nlohmann::json;
  json balance = {{"ranks", f.ranks},
                  {"blocks", {f.blocks[0], f.blocks[1], f.blocks[2]}},
                  {"owned_particles", toJson(f.owned)},
                  {"ghosts", toJson(f.ghosts)},
                  {"candidate_pairs", toJson(f.candidate_pairs)},
                  {"evaluated_pairs", toJson(f.evaluated_pairs)},
                  {"early_pairs", toJson(f.early_pairs)},
                  {"contacts", toJson(f.contacts)},
                  {"work", toJson(f.work)},
                  {"modelled_efficiency", modelledEfficiency(f)},
                  {"bytes_sent_last_step", toJson(f.bytes_last_step)},
                  {"messages_sent_last_step", toJson(f.messages_last_step)},
                  {"bytes_sent_per_step", toJson(f.bytes_per_step)},
                  {"messages_sent_per_step", toJson(f.messages_per_step)}};
  json times = {{"wait", toJson(f.wait_seconds)},
                {"transfer", toJson(f.transfer_seconds)},
                {"bookkeeping", toJson(f.bookkeeping_seconds)},
                {"early_contact_work", toJson(f.early_seconds)}};
  return {{"balance", balance}, {"communication_seconds_per_step", times}};
}

}  // namespace polydem::sim
