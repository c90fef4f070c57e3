// Checkpoint and restart of a Simulation: N steps, a checkpoint file, a restart, M more steps end
// in the same bits (hash of every particle and pair history) as N + M uninterrupted steps, in the
// equilibrium stage and in the main stage, on the same and on other rank counts. The scene is
// the sliding heap of rank_determinism_test (sliding_heap.h), so that pairs with tangential
// histories cross rank borders.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>

#include "generators/pile_scene.h"
#include "polydem/checkpoint/checkpoint.h"
#include "polydem/core/error.h"
#include "polydem/core/logging.h"
#include "polydem/core/mpi_env.h"
#include "polydem/run/run.h"
#include "polydem/scene/scene_reader.h"
#include "polydem/sim/simulation.h"
#include "sliding_heap.h"

namespace polydem::sim {
namespace {

namespace fs = std::filesystem;

constexpr std::int64_t kFirst = 400;   // steps before the checkpoint
constexpr std::int64_t kSecond = 300;  // steps after it

setup::Setup crossingScene(bool equilibrium) {
  // Cubes in a lattice only 2% apart: contacts from the first steps.
  setup::Setup s = testing::slidingHeap("cubes", 0.02);
  s.steps = kFirst + kSecond;
  s.end_time.reset();
  if (equilibrium) {
    // A stage that ends by its step limit, after the checkpoint, then a short main stage.
    s.equilibrium.enabled = true;
    s.equilibrium.force_ratio = 1e-300;
    s.equilibrium.max_steps = kFirst + kSecond;
    s.equilibrium.reset_velocities = false;
    s.steps = 60;
  }
  return s;
}

/// A communicator of the first `n` ranks of the world (MPI_COMM_NULL on the others).
MPI_Comm firstRanks(int n) {
  MPI_Comm c;
  MPI_Comm_split(MPI_COMM_WORLD, mpi::rank() < n ? 0 : MPI_UNDEFINED, mpi::rank(), &c);
  return c;
}

/// Runs `f` on the first `n` ranks and broadcasts its result from rank 0 to all.
template <typename F>
std::uint64_t onFirst(int n, F f) {
  std::uint64_t result = 0;
  MPI_Comm c = firstRanks(n);
  if (c != MPI_COMM_NULL) {
    result = f(c);
    MPI_Comm_free(&c);
  }
  MPI_Bcast(&result, 1, MPI_UINT64_T, 0, MPI_COMM_WORLD);
  return result;
}

/// The uninterrupted run: both stages to the end.
std::uint64_t straight(const setup::Setup& scene, MPI_Comm comm) {
  Simulation sim(scene, comm);
  sim.runEquilibrium();
  sim.run();
  const auto h = sim.stateHash();
  EXPECT_EQ(h.history_conflicts, 0);
  EXPECT_GT(h.pair_count, 10) << "the scene should have many contact histories";
  return h.combined;
}

fs::path sharedPath(const std::string& name) {
  // The same on every rank: rank 0's pid.
  long pid = static_cast<long>(getpid());
  MPI_Bcast(&pid, 1, MPI_LONG, 0, MPI_COMM_WORLD);
  return fs::temp_directory_path() / ("polydem_restart_" + std::to_string(pid) + "_" + name);
}

/// Runs the scene on `comm` until `kFirst` steps of the scene's first stage, then writes `path`.
void writeAfterFirst(const setup::Setup& scene, const fs::path& path, MPI_Comm comm) {
  Simulation sim(scene, comm);
  sim.setStepHook([&sim] { return sim.stepCount() == kFirst; });
  if (scene.equilibrium.enabled) {
    sim.runEquilibrium();
    ASSERT_EQ(sim.stage(), Stage::kEquilibrium) << "the hook should interrupt the stage";
  } else {
    EXPECT_EQ(sim.run(), timeloop::StopReason::kUserCondition);
  }
  ASSERT_EQ(sim.stepCount(), kFirst);
  const sim::CheckpointData data = sim.checkpoint("", scene.file, "{}");
  std::int64_t sliding = 0;  // springs with a tangential force to carry over
  for (const auto& h : data.pair_histories) sliding += h.touching && h.shear_force.norm() > 0;
  for (const auto& h : data.sub_histories) sliding += h.shear_force.norm() > 0;
  EXPECT_GT(mpi::allreduceSum(sliding, comm), 10) << "the checkpoint should hold shear histories";
  checkpoint::writeCheckpoint(path, data, comm);
  // Written from the table in place (no copy of the history), in rounds of a few rows: the same
  // datasets, bit for bit.
  const fs::path streamed = path.string() + ".streamed";
  hdf5::CheckpointIoOptions small;
  small.round_bytes = 4096;
  checkpoint::writeCheckpoint(streamed, sim.checkpointForWriting("", scene.file, "{}"), comm,
                              small);
  const auto copied = checkpoint::verifyCheckpoint(path, comm).datasets;
  const auto in_place = checkpoint::verifyCheckpoint(streamed, comm).datasets;
  ASSERT_EQ(copied.size(), in_place.size());
  for (std::size_t i = 0; i < copied.size(); ++i) {
    EXPECT_EQ(copied[i].name, in_place[i].name);
    EXPECT_EQ(copied[i].checksum, in_place[i].checksum) << copied[i].name;
  }
  MPI_Barrier(comm);
  if (mpi::rank(comm) == 0) fs::remove(streamed);
}

/// Runs a restarted simulation's both stages to the end.
std::uint64_t finish(const setup::Setup& scene, Simulation& sim) {
  EXPECT_EQ(sim.stepCount(), kFirst);
  EXPECT_EQ(sim.stage(), scene.equilibrium.enabled ? Stage::kEquilibrium : Stage::kMain);
  sim.runEquilibrium();
  sim.run();
  const auto h = sim.stateHash();
  EXPECT_EQ(h.history_conflicts, 0);
  return h.combined;
}

/// Reads `path` on `comm` and runs both stages to the end.
std::uint64_t restartFrom(const setup::Setup& scene, const fs::path& path, MPI_Comm comm) {
  const sim::CheckpointData data = checkpoint::readCheckpoint(path, comm);
  Simulation sim(scene, data, path.string(), comm);
  return finish(scene, sim);
}

/// The same with the pair histories read from the file in rounds of a few rows, each routed and
/// merged as it comes.
std::uint64_t restartInChunks(const setup::Setup& scene, const fs::path& path, MPI_Comm comm) {
  hdf5::CheckpointIoOptions small;
  small.round_bytes = 4096;
  checkpoint::CheckpointReader reader(path, comm, small);
  EXPECT_TRUE(reader.data().pair_keys.empty() && reader.data().sub_keys.empty());
  Simulation sim(scene, reader.data(), reader, path.string(), comm);
  EXPECT_GT(sim.restoreRouting().chunks, 2) << "the histories should come in several chunks";
  return finish(scene, sim);
}

void expectRestartSameBits(const setup::Setup& scene, const std::string& name) {
  log::setLevel(log::Level::kWarning);
  const int p = mpi::size();
  const std::uint64_t reference = onFirst(1, [&](MPI_Comm c) { return straight(scene, c); });
  const fs::path path = sharedPath(name + ".h5");
  // Written and read on all ranks.
  writeAfterFirst(scene, path, MPI_COMM_WORLD);
  EXPECT_EQ(restartFrom(scene, path, MPI_COMM_WORLD), reference) << "restart on " << p << " ranks";
  EXPECT_EQ(restartInChunks(scene, path, MPI_COMM_WORLD), reference)
      << "restart on " << p << " ranks, the histories in chunks";
  // Written on all ranks, read on one and on P - 1.
  EXPECT_EQ(onFirst(1, [&](MPI_Comm c) { return restartFrom(scene, path, c); }), reference)
      << "written on " << p << " ranks, read on 1";
  if (p > 2) {
    EXPECT_EQ(onFirst(p - 1, [&](MPI_Comm c) { return restartFrom(scene, path, c); }), reference)
        << "written on " << p << " ranks, read on " << p - 1;
  }
  // Written on two ranks, read on three.
  if (p >= 3) {
    onFirst(2, [&](MPI_Comm c) {
      writeAfterFirst(scene, path, c);
      return std::uint64_t{0};
    });
    EXPECT_EQ(onFirst(3, [&](MPI_Comm c) { return restartFrom(scene, path, c); }), reference)
        << "written on 2 ranks, read on 3";
    EXPECT_EQ(onFirst(3, [&](MPI_Comm c) { return restartInChunks(scene, path, c); }), reference)
        << "written on 2 ranks, read on 3, the histories in chunks";
  }
  if (mpi::rank() == 0) fs::remove(path);
}

TEST(Restart, MainStageSameBitsOnAnyRankCount) {
  // With the default decomposition: blocks fitted to the particles (again, for the reading rank
  // count, on a restart), balanced by their contacts, weighed again every 100 steps. (The
  // equilibrium test below keeps the sliding heap's small cyclic blocks.)
  setup::Setup s = crossingScene(false);
  s.domain.blocks.reset();
  s.domain.balancer = "metis";
  s.domain.rebalance_every = 100;
  expectRestartSameBits(s, "main");
}

TEST(Restart, EquilibriumStageSameBitsOnAnyRankCount) {
  expectRestartSameBits(crossingScene(true), "equilibrium");
}

TEST(Restart, RefusesShapesThatDoNotMatch) {
  log::setLevel(log::Level::kWarning);
  setup::Setup scene = crossingScene(false);
  const fs::path path = sharedPath("shapes.h5");
  writeAfterFirst(scene, path, MPI_COMM_WORLD);
  const sim::CheckpointData data = checkpoint::readCheckpoint(path, MPI_COMM_WORLD);
  setup::Setup moved = scene;
  moved.shapes[0].vertices[0] *= 1.0 + 1e-12;  // one bit is enough
  try {
    Simulation sim(moved, data, path.string(), MPI_COMM_WORLD);
    ADD_FAILURE() << "a checkpoint with other shapes was accepted";
  } catch (const CheckpointError& e) {
    EXPECT_NE(std::string(e.what()).find(path.string()), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("shape"), std::string::npos) << e.what();
  }
  setup::Setup other_dt = scene;
  other_dt.dt *= 0.5;
  EXPECT_THROW(Simulation(other_dt, data, path.string(), MPI_COMM_WORLD), CheckpointError);
  setup::Setup no_equilibrium = crossingScene(true);
  no_equilibrium.equilibrium.enabled = false;
  const fs::path eq_path = sharedPath("eq.h5");
  writeAfterFirst(crossingScene(true), eq_path, MPI_COMM_WORLD);
  const sim::CheckpointData eq_data = checkpoint::readCheckpoint(eq_path, MPI_COMM_WORLD);
  EXPECT_THROW(Simulation(no_equilibrium, eq_data, eq_path.string(), MPI_COMM_WORLD),
               CheckpointError);
  MPI_Barrier(MPI_COMM_WORLD);
  if (mpi::rank() == 0) {
    fs::remove(path);
    fs::remove(eq_path);
  }
}

// A version-1 file, written by polydem before sub-contacts (tests/sim/data: four cubes sliding
// on a plate, checkpoint at step 200 of 400), continues the run it holds: with the point model
// that wrote it, to the same bits as that model running the scene straight through. (With
// sub-contacts, the default now, the continuation would be another run.)
TEST(Restart, VersionOneFileContinuesWithThePointModel) {
  log::setLevel(log::Level::kWarning);
  const std::string dir = POLYDEM_TEST_DATA_DIR;
  const sim::CheckpointData data =
      checkpoint::readCheckpoint(dir + "/checkpoint_v1_step200.h5", MPI_COMM_WORLD);
  ASSERT_EQ(data.format_version, 1);
  EXPECT_TRUE(data.sub_keys.empty());
  EXPECT_GT(data.pair_keys.size(), 0u);
  const auto continued =
      run::continueRun(dir + "/checkpoint_v1_step200.h5", dir + "/v1-restart.toml",
                       run::RunOptions{}, MPI_COMM_WORLD);
  setup::Setup point = scene::readScene(dir + "/v1-restart.toml");
  point.contact_model = "point";
  const auto straight = run::runScene(point, run::RunOptions{}, MPI_COMM_WORLD);
  EXPECT_EQ(continued.hash.combined, straight.hash.combined);
  setup::Setup subcontacts = scene::readScene(dir + "/v1-restart.toml");
  EXPECT_NE(run::runScene(subcontacts, run::RunOptions{}, MPI_COMM_WORLD).hash.combined,
            straight.hash.combined)
      << "the two models should differ on this scene, or the test shows nothing";
}

// A run whose kernel and contact model the command line set (polydem run --kernel fcp
// --contact-model point) continues from its checkpoints with them, not with the stored scene's
// (which say gjk-epa-ipm and sub-contacts): the same bits as the run straight through.
TEST(Restart, CommandLineSettingsCarryOver) {
  log::setLevel(log::Level::kWarning);
  const std::string dir = POLYDEM_TEST_DATA_DIR;
  const std::string text = scene::readSceneText(dir + "/v1-restart.toml");
  const setup::Setup scene = scene::parseScene(text, "v1-restart.toml");
  const fs::path out = sharedPath("settings"), out2 = sharedPath("settings2");
  run::RunOptions first;
  first.out_dir = out.string();
  first.snapshots = false;
  first.scene_text = text;
  first.kernel = "fcp";
  first.contact_model = "point";
  first.checkpoint_every = 200;
  const auto straight = run::runScene(scene, first, MPI_COMM_WORLD);
  run::RunOptions second;
  second.out_dir = out2.string();
  second.snapshots = false;
  std::string at_200;  // the run's checkpoint of step 200 (its name carries the run's id)
  for (const auto& f : checkpoint::listCheckpoints(out / "checkpoints")) {
    if (f.step == 200) at_200 = f.path.string();
  }
  ASSERT_FALSE(at_200.empty()) << "no checkpoint of step 200 in " << out / "checkpoints";
  const auto continued = run::continueRun(at_200, std::nullopt, second, MPI_COMM_WORLD);
  EXPECT_EQ(continued.hash.combined, straight.hash.combined);
  EXPECT_NE(run::runScene(scene, run::RunOptions{}, MPI_COMM_WORLD).hash.combined,
            straight.hash.combined)
      << "the scene's own settings should give another run, or the test shows nothing";
  MPI_Barrier(MPI_COMM_WORLD);
  if (mpi::rank() == 0) {
    fs::remove_all(out);
    fs::remove_all(out2);
  }
}

}  // namespace
}  // namespace polydem::sim
