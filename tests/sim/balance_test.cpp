// The default decomposition balances the work: on a dense pack of cubes in its box
// (P-PILE) and on the same pack on a floor twice as wide (where blocks cut from the domain box
// alone leave the pile in a few blocks), every rank's kernel calls are within 10 % of the mean
// on 2, 8 and 16 ranks. Counts only, never a time: they hold on oversubscribed ranks.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "generators/pile_scene.h"
#include "polydem/core/logging.h"
#include "polydem/core/mpi_env.h"
#include "polydem/core/strings.h"
#include "polydem/domain/block_forest.h"
#include "polydem/run/run.h"
#include "polydem/sim/balance_figures.h"
#include "polydem/sim/simulation.h"

namespace polydem::sim {
namespace {

setup::Setup densePack(double floor_width) {
  PileOptions o;
  o.particles = 4000;  // 20 x 20 x 10
  o.layers = 10;
  o.shapes = "cubes";
  o.gap = -0.001;  // every face in contact from the first step
  o.floor_width = floor_width;
  return makePileScene(o);
}

BalanceFigures afterOneStep(const setup::Setup& scene) {
  Simulation sim(scene, MPI_COMM_WORLD);
  sim.step();
  return balanceFigures(sim);
}

void expectBalanced(const BalanceFigures& f, const char* scene) {
  SCOPED_TRACE(cat(scene, " on ", f.ranks, " ranks, ", f.blocks[0], " x ", f.blocks[1], " x ",
                   f.blocks[2], " blocks"));
  EXPECT_GT(f.evaluated_pairs.min, 0) << "a rank without pairs";
  EXPECT_LE(f.evaluated_pairs.ratio(), 1.10);
  EXPECT_LE(f.candidate_pairs.ratio(), 1.10);
  EXPECT_LE(f.contacts.ratio(), 1.10);
  EXPECT_LE(f.work.ratio(), 1.10);
  EXPECT_GT(f.owned.min, 0);
  if (f.ranks > 1) {
    // One message per neighbour and step, never more than there are other ranks.
    EXPECT_GT(f.messages_per_step.min, 0);
    EXPECT_LE(f.messages_per_step.max, f.ranks - 1);
  }
}

TEST(Balance, DensePackInItsBox) {
  log::setLevel(log::Level::kWarning);
  expectBalanced(afterOneStep(densePack(0)), "P-PILE dense pack");
}

TEST(Balance, DensePackOnAFloorTwiceAsWide) {
  log::setLevel(log::Level::kWarning);
  const setup::Setup scene = densePack(2);
  const BalanceFigures f = afterOneStep(scene);
  expectBalanced(f, "dense pack on a wide floor");
  // The old default for contrast (blocks from the domain box alone, about 8 per rank): the pile
  // sits in a few blocks and no rebalancing can share them out.
  if (mpi::size() > 1) {
    setup::Setup old = scene;
    Simulation probe(scene, MPI_COMM_WORLD);
    old.domain.blocks = domain::chooseBlockCounts(probe.forest().domain(), mpi::size(), 8);
    EXPECT_GT(afterOneStep(old).evaluated_pairs.ratio(), 1.5)
        << "the domain-only blocks should fail here, or this test shows nothing";
  }
}

TEST(Balance, SummaryJsonCarriesThePerRankFigures) {
  log::setLevel(log::Level::kWarning);
  long pid = static_cast<long>(getpid());
  MPI_Bcast(&pid, 1, MPI_LONG, 0, MPI_COMM_WORLD);
  const auto dir = std::filesystem::temp_directory_path() / cat("polydem_balance_", pid);
  run::RunOptions options;
  options.out_dir = dir.string();
  options.snapshots = false;
  options.steps = 3;
  run::runScene(densePack(2), options, MPI_COMM_WORLD);
  if (mpi::rank() != 0) return;
  nlohmann::json j;
  std::ifstream(dir / "summary.json") >> j;
  std::filesystem::remove_all(dir);
  const auto& b = j.at("balance");
  const int ranks = mpi::size();
  EXPECT_EQ(b.at("ranks"), ranks);
  for (const char* key : {"owned_particles", "ghosts", "candidate_pairs", "evaluated_pairs",
                          "contacts", "work", "bytes_sent_per_step", "messages_sent_per_step"}) {
    SCOPED_TRACE(key);
    const auto& s = b.at(key);
    EXPECT_LE(s.at("min").get<double>(), s.at("mean").get<double>());
    EXPECT_LE(s.at("mean").get<double>(), s.at("max").get<double>());
  }
  EXPECT_DOUBLE_EQ(b["owned_particles"]["mean"].get<double>() * ranks, 4000.0);
  EXPECT_LE(b["evaluated_pairs"]["max_over_mean"].get<double>(), 1.10);
  EXPECT_LE(b["messages_sent_per_step"]["max"].get<double>(), ranks - 1);
  EXPECT_GE(b["rebalancing"]["balance_checks"].get<int>(), 1);
  for (const char* key : {"wait", "transfer", "bookkeeping"}) {
    EXPECT_TRUE(j.at("communication_seconds_per_step").contains(key)) << key;
  }
}

}  // namespace
}  // namespace polydem::sim
