// `polydem fos` runs its trials side by side on groups of the ranks: each trial must end in the
// same bits as the same trial run alone on one rank (state hash, outcome, displacement, time).
#include <gtest/gtest.h>

#include <cstring>
#include <set>

#include "polydem/core/logging.h"
#include "polydem/core/mpi_env.h"
#include "polydem/run/fos.h"
#include "polydem/scene/scene_reader.h"

namespace polydem::sim {
namespace {

std::uint64_t bits(double x) {
  std::uint64_t b = 0;
  std::memcpy(&b, &x, sizeof b);
  return b;
}

TEST(FosGroups, EachTrialIsTheSameBitsAsAlone) {
  log::setLevel(log::Level::kWarning);
  setup::Setup scene =
      scene::readScene(std::string(POLYDEM_SCENES_DIR) + "/examples/fos-wedge.toml");
  scene.fos.resolution = 0.2;  // a few rounds are enough to compare trials
  const run::FosCriterion criterion = run::fosCriterion(scene);
  const int ranks = mpi::size();
  const int groups = ranks >= 2 ? ranks / 2 : 1;  // two ranks per trial where there are four
  const run::FosResult all = run::findFactorOfSafety(scene, criterion, groups, MPI_COMM_WORLD);
  ASSERT_GE(all.trials.size(), 3u);
  EXPECT_EQ(all.groups, groups);
  std::set<int> used;
  for (const run::FosTrial& t : all.trials) used.insert(t.group);
  EXPECT_EQ(static_cast<int>(used.size()), groups) << "every group should have run trials";

  MPI_Comm self;
  MPI_Comm_split(MPI_COMM_WORLD, mpi::rank() == 0 ? 0 : MPI_UNDEFINED, 0, &self);
  if (self == MPI_COMM_NULL) return;
  for (const run::FosTrial& t : all.trials) {
    const run::FosTrial alone = run::runFosTrial(scene, t.factor, criterion, self);
    EXPECT_EQ(alone.state_hash, t.state_hash) << "F = " << t.factor << " (group " << t.group << ")";
    EXPECT_EQ(alone.outcome, t.outcome) << "F = " << t.factor;
    EXPECT_EQ(bits(alone.mean_displacement), bits(t.mean_displacement)) << "F = " << t.factor;
    EXPECT_EQ(bits(alone.time), bits(t.time)) << "F = " << t.factor;
    EXPECT_EQ(alone.steps, t.steps);
    EXPECT_EQ(alone.history.size(), t.history.size());
  }
  MPI_Comm_free(&self);
}

}  // namespace
}  // namespace polydem::sim
