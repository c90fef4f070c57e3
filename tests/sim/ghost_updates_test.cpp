// Exchanging only what changed: in a dense pack, whose ghosts stay ghosts on the same
// ranks step after step, the exchange sends a kept ghost's changing state (104 bytes) instead of
// its whole record (134 bytes), and the run ends in the same bits as with whole records every
// step. Counts only, never a time: it holds on oversubscribed ranks.
#include <gtest/gtest.h>

#include <set>

#include "generators/pile_scene.h"
#include "polydem/core/logging.h"
#include "polydem/core/mpi_env.h"
#include "polydem/sim/simulation.h"

namespace polydem::sim {
namespace {

setup::Setup densePack() {
  PileOptions o;
  o.particles = 1600;  // 20 x 20 x 4
  o.layers = 4;
  o.shapes = "cubes";
  o.gap = -0.001;  // every face in contact from the first step
  return makePileScene(o);
}

struct Outcome {
  std::uint64_t hash = 0;
  std::int64_t bytes = 0;                        // all ranks, the steps after the first
  std::int64_t ghosts_sent = 0;                  // all ranks, the steps after the first
  std::int64_t updates_sent = 0;                 // of those, as state updates
  std::multiset<std::vector<std::byte>> ghosts;  // this rank's, every bit
};

Outcome run(bool compact, int steps) {
  Simulation sim(densePack(), MPI_COMM_WORLD);
  sim.setCompactGhosts(compact);
  sim.step();  // the first exchange sends every ghost whole either way
  const comm::ExchangeStats first = sim.stepExchangeTotals();
  for (int i = 1; i < steps; ++i) sim.step();
  const comm::ExchangeStats all = sim.stepExchangeTotals();
  Outcome out;
  out.hash = sim.stateHash().combined;
  out.bytes = mpi::allreduceSum(all.bytes_sent - first.bytes_sent);
  out.ghosts_sent = mpi::allreduceSum(all.particles_sent - first.particles_sent);
  out.updates_sent = mpi::allreduceSum(all.ghost_updates_sent - first.ghost_updates_sent);
  const auto& s = sim.particles();
  for (std::size_t i = s.localCount(); i < s.size(); ++i) {
    SendBuffer b;
    pack(b, s[i]);
    b << s.shift(i);
    out.ghosts.insert(b.bytes());
  }
  return out;
}

TEST(GhostUpdates, DensePackSendsFewerBytesWithTheSameBits) {
  log::setLevel(log::Level::kWarning);
  const int steps = 6;
  const Outcome updates = run(true, steps), records = run(false, steps);
  EXPECT_EQ(updates.hash, records.hash);
  EXPECT_EQ(updates.ghosts, records.ghosts);
  EXPECT_EQ(records.updates_sent, 0);
  EXPECT_EQ(updates.ghosts_sent, records.ghosts_sent);
  if (mpi::size() == 1) return;
  ASSERT_GT(records.ghosts_sent, 0) << "no ghosts: this test shows nothing";
  // The pack hardly moves: nearly every ghost stays where it was.
  EXPECT_GE(static_cast<double>(updates.updates_sent), 0.95 * updates.ghosts_sent);
  // 104 + 1/8 bytes (state and its keep bit) instead of 134 per kept ghost: 0.78 of the bytes.
  EXPECT_LT(static_cast<double>(updates.bytes), 0.80 * static_cast<double>(records.bytes));
  if (mpi::rank() == 0) {
    std::printf("bytes after the first step, all ranks: %lld with updates, %lld whole (%.3f)\n",
                static_cast<long long>(updates.bytes), static_cast<long long>(records.bytes),
                static_cast<double>(updates.bytes) / static_cast<double>(records.bytes));
  }
}

}  // namespace
}  // namespace polydem::sim
