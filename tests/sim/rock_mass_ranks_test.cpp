// A scene with a [[rock_mass]] (jittered joint sets, a fault fixing the rock below it) gives the
// same blocks on every rank, and its run ends in the same state on one rank and on all of them.
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>

#include "polydem/checkpoint/checkpoint.h"
#include "polydem/core/logging.h"
#include "polydem/core/mpi_env.h"
#include "polydem/core/state_hash.h"
#include "polydem/scene/scene_reader.h"
#include "polydem/sim/simulation.h"

namespace polydem::sim {
namespace {

const char* kScene = R"(
[scene]
id = "T-ROCK-MASS"
[simulation]
kernel = "gjk-epa-ipm"
dt = "2e-4 s"
steps = 300
[domain]
blocks = [4, 2, 2]
[[material]]
name = "rock"
density = 2600
kn = "1 GN/m"
ks = "0.5 GN/m"
friction_angle = 20
local_damping = 0.1
[[rock_mass]]
name = "m"
material = "rock"
min_volume = "0.05 m^3"
region = { type = "profile", profile = [[0, -2], [12, -2], [12, 0], [4, 6], [0, 6]], y = [0, 4] }
[[rock_mass.plane]]
name = "base"
dip = 25
dip_direction = 90
point = [4, 0, 1]
fixed = "below"
[[rock_mass.joint_set]]
name = "J1"
dip = 75
dip_direction = 260
spacing = "1.2 m"
spacing_jitter = 0.3
orientation_jitter = 6
seed = 4
[[rock_mass.joint_set]]
name = "J2"
dip = 80
dip_direction = 5
spacing = "1.5 m"
orientation_jitter = 4
seed = 5
)";

std::uint64_t blockDigest(const setup::Setup& scene) {
  BitHasher h;
  for (const auto& shape : scene.shapes) {
    for (const Vec3& v : shape.vertices) h.add(v);
  }
  for (const auto& p : scene.particles) h.add(static_cast<std::uint64_t>(p.fixed));
  return h.value();
}

TEST(RockMassRanks, SameBlocksAndSameRunOnAnyRankCount) {
  log::setLevel(log::Level::kWarning);
  const setup::Setup scene = scene::parseScene(kScene, "rock_mass_ranks.toml");
  ASSERT_EQ(scene.rock_masses.size(), 1u);
  EXPECT_GT(scene.rock_masses[0].report.free_blocks, 15);
  // Every rank cut the same blocks.
  const std::uint64_t mine = blockDigest(scene);
  std::uint64_t lowest = 0, highest = 0;
  MPI_Allreduce(&mine, &lowest, 1, MPI_UINT64_T, MPI_MIN, MPI_COMM_WORLD);
  MPI_Allreduce(&mine, &highest, 1, MPI_UINT64_T, MPI_MAX, MPI_COMM_WORLD);
  EXPECT_EQ(lowest, highest);

  std::uint64_t reference = 0;
  MPI_Comm self;
  MPI_Comm_split(MPI_COMM_WORLD, mpi::rank() == 0 ? 0 : MPI_UNDEFINED, 0, &self);
  if (self != MPI_COMM_NULL) {
    Simulation alone(scene, self);
    alone.run();
    reference = alone.stateHash().combined;
    MPI_Comm_free(&self);
  }
  MPI_Bcast(&reference, 1, MPI_UINT64_T, 0, MPI_COMM_WORLD);
  Simulation all(scene, MPI_COMM_WORLD);
  all.run();
  const auto hash = all.stateHash();
  EXPECT_GT(hash.pair_count, 20);
  EXPECT_EQ(hash.history_conflicts, 0);
  EXPECT_EQ(hash.combined, reference) << "state differs between 1 and " << mpi::size() << " ranks";
}

// The same rock mass with a joint on each plane (cohesion and tensile strength as stresses): the
// contacts on the planes take their joints, which changes the run, and the run is the same on
// one rank, on all of them, and continued from a checkpoint taken half way.
TEST(RockMassRanks, JointsGiveTheSameRunOnAnyRankCountAndAfterARestart) {
  log::setLevel(log::Level::kWarning);
  std::string text = kScene;
  const auto insert = [&](const std::string& after, const std::string& what) {
    const std::size_t at = text.find(after);
    ASSERT_NE(at, std::string::npos) << after;
    text.insert(at + after.size(), what);
  };
  insert("local_damping = 0.1\n",
         "[[joint]]\nname = \"weak\"\njkn = \"2 GPa/m\"\njks = \"1 GPa/m\"\n"
         "friction_angle = 15\ncohesion = \"5 kPa\"\ntensile_strength = \"2 kPa\"\n"
         "[[joint]]\nname = \"strong\"\njkn = \"2 GPa/m\"\njks = \"1 GPa/m\"\n"
         "friction_angle = 35\n");
  insert("fixed = \"below\"\n", "joint = \"strong\"\n");
  insert("seed = 4\n", "joint = \"weak\"\n");
  const setup::Setup scene = scene::parseScene(text, "rock_mass_joints.toml");
  const setup::Setup plain = scene::parseScene(kScene, "rock_mass_ranks.toml");
  ASSERT_EQ(scene.joints.size(), 2u);

  std::uint64_t reference = 0, without_joints = 0;
  int joint_contacts = 0;
  MPI_Comm self;
  MPI_Comm_split(MPI_COMM_WORLD, mpi::rank() == 0 ? 0 : MPI_UNDEFINED, 0, &self);
  if (self != MPI_COMM_NULL) {
    Simulation alone(scene, self);
    alone.run();
    reference = alone.stateHash().combined;
    for (const auto& r : alone.contacts().records()) joint_contacts += r.touching && r.joint >= 0;
    Simulation no_joints(plain, self);
    no_joints.run();
    without_joints = no_joints.stateHash().combined;
    MPI_Comm_free(&self);
  }
  MPI_Bcast(&reference, 1, MPI_UINT64_T, 0, MPI_COMM_WORLD);
  MPI_Bcast(&without_joints, 1, MPI_UINT64_T, 0, MPI_COMM_WORLD);
  MPI_Bcast(&joint_contacts, 1, MPI_INT, 0, MPI_COMM_WORLD);
  EXPECT_GT(joint_contacts, 10);
  EXPECT_NE(reference, without_joints) << "the joints changed nothing";

  Simulation all(scene, MPI_COMM_WORLD);
  all.run();
  EXPECT_EQ(all.stateHash().combined, reference)
      << "state differs between 1 and " << mpi::size() << " ranks";

  setup::Setup first_half = scene;
  first_half.steps = *scene.steps / 2;
  Simulation before(first_half, MPI_COMM_WORLD);
  before.run();
  // Through a checkpoint file: the faces' joint planes travel in /shapes/face_plane.
  int pid = static_cast<int>(getpid());
  MPI_Bcast(&pid, 1, MPI_INT, 0, MPI_COMM_WORLD);
  const auto path = std::filesystem::temp_directory_path() /
                    ("polydem_rock_mass_joints_" + std::to_string(pid) + ".h5");
  checkpoint::writeCheckpoint(path, before.checkpoint(text, "rock_mass_joints.toml", "{}"),
                              MPI_COMM_WORLD);
  const CheckpointData saved = checkpoint::readCheckpoint(path, MPI_COMM_WORLD);
  MPI_Barrier(MPI_COMM_WORLD);
  if (mpi::rank() == 0) std::filesystem::remove(path);
  ASSERT_EQ(saved.shapes.size(), scene.shapes.size());
  int tagged = 0;
  for (const auto& shape : saved.shapes) {
    ASSERT_TRUE(shape.face_plane.has_value());
    for (const std::int32_t id : *shape.face_plane) tagged += id >= 0;
  }
  EXPECT_GT(tagged, 20) << "faces with a joint plane in the file";
  Simulation after(scene, saved, path.string(), MPI_COMM_WORLD);
  after.run();
  EXPECT_EQ(after.stateHash().combined, reference) << "a restart changed the run";
}

}  // namespace
}  // namespace polydem::sim
