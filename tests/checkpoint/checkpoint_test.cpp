// Checkpoint round trips: every field comes back bit for bit, read on the rank count that wrote
// it and on another one (a split of the launched ranks), and the checksum of a dataset does not
// depend on how many ranks wrote it.
#include "polydem/checkpoint/checkpoint.h"

#include <gtest/gtest.h>
#include <mpi.h>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <nlohmann/json.hpp>

#include "checkpoint_test_data.h"
#include "polydem/core/mpi_env.h"
#include "polydem/core/state_hash.h"
#include "polydem/hdf5/checksum.h"

namespace polydem::checkpoint {
namespace {

using testing::gatherFree;
using testing::gatherPairs;
using testing::makeTruth;
using testing::shareOf;
using testing::Truth;

bool sameBits(double a, double b) {
  return std::memcmp(&a, &b, sizeof a) == 0;
}
bool sameBits(const Vec3& a, const Vec3& b) {
  return std::memcmp(a.data(), b.data(), 24) == 0;
}

/// The replicated part of `read` equals `truth` bit for bit.
void expectReplicated(const sim::CheckpointData& read, const sim::CheckpointData& truth) {
  EXPECT_EQ(read.format_version, kCheckpointFormatVersion);
  EXPECT_EQ(read.code_version, truth.code_version);
  EXPECT_EQ(read.scene_toml, truth.scene_toml);
  EXPECT_EQ(read.scene_file, truth.scene_file);
  EXPECT_EQ(read.scene_hash, hdf5::checksumOfBytes(truth.scene_toml));
  EXPECT_EQ(read.step, truth.step);
  EXPECT_TRUE(sameBits(read.time, truth.time));
  EXPECT_EQ(read.time_digits, truth.time_digits);
  EXPECT_TRUE(sameBits(read.dt, truth.dt));
  EXPECT_EQ(read.stage, truth.stage);
  EXPECT_EQ(read.equilibrium_steps, truth.equilibrium_steps);
  EXPECT_EQ(read.equilibrium_reached, truth.equilibrium_reached);
  EXPECT_EQ(read.run_state, truth.run_state);
  ASSERT_EQ(read.shapes.size(), truth.shapes.size());
  for (std::size_t s = 0; s < truth.shapes.size(); ++s) {
    const auto &a = read.shapes[s], &b = truth.shapes[s];
    EXPECT_EQ(a.name, b.name);
    ASSERT_EQ(a.vertices.size(), b.vertices.size());
    for (std::size_t v = 0; v < a.vertices.size(); ++v) {
      EXPECT_TRUE(sameBits(a.vertices[v], b.vertices[v]));
    }
    EXPECT_EQ(a.faces, b.faces);
    EXPECT_TRUE(sameBits(a.volume, b.volume));
    EXPECT_TRUE(sameBits(a.principal_moments, b.principal_moments));
    EXPECT_TRUE(sameBits(a.circumradius, b.circumradius));
    EXPECT_TRUE(sameBits(a.inradius, b.inradius));
  }
  ASSERT_EQ(read.materials.size(), truth.materials.size());
  for (std::size_t m = 0; m < truth.materials.size(); ++m) {
    const auto &a = read.materials[m], &b = truth.materials[m];
    EXPECT_EQ(a.name, b.name);
    for (auto field : {&particles::Material::density, &particles::Material::kn,
                       &particles::Material::ks, &particles::Material::friction_angle,
                       &particles::Material::cohesion, &particles::Material::normal_damping,
                       &particles::Material::local_damping, &particles::Material::penalty}) {
      EXPECT_TRUE(sameBits(a.*field, b.*field)) << a.name;
    }
  }
  ASSERT_EQ(read.interactions.size(), truth.interactions.size());
  for (std::size_t i = 0; i < truth.interactions.size(); ++i) {
    const auto &a = read.interactions[i], &b = truth.interactions[i];
    EXPECT_EQ(a.a, b.a);
    EXPECT_EQ(a.b, b.b);
    EXPECT_EQ(std::memcmp(&a.properties, &b.properties, sizeof a.properties), 0);
  }
  EXPECT_TRUE(sameBits(read.domain.lo, truth.domain.lo));
  EXPECT_TRUE(sameBits(read.domain.hi, truth.domain.hi));
  EXPECT_EQ(read.domain.blocks, truth.domain.blocks);
  EXPECT_EQ(read.domain.periodic, truth.domain.periodic);
  EXPECT_EQ(read.domain.rank_map, truth.domain.rank_map);
  EXPECT_EQ(read.domain.ranks, truth.domain.ranks);
}

/// Every rank of `comm` holds every replicated particle once; the free particles and pairs of all
/// ranks together are the truth's, each once, bit for bit.
void expectDistributed(const sim::CheckpointData& read, const Truth& truth, MPI_Comm comm) {
  std::vector<std::vector<std::byte>> globals;
  for (const auto& p : read.particles) {
    if (p.isGlobal()) globals.push_back(testing::bytesOf(p));
  }
  ASSERT_EQ(globals.size(), truth.globals.size());
  for (std::size_t i = 0; i < globals.size(); ++i) {
    EXPECT_EQ(globals[i], testing::bytesOf(truth.globals[i])) << "replicated particle " << i;
  }
  const auto free = gatherFree(read, comm);
  ASSERT_EQ(free.size(), truth.free.size());
  for (const auto& p : truth.free) {
    const auto it = free.find(p.uid);
    ASSERT_NE(it, free.end()) << "uid " << p.uid;
    EXPECT_EQ(it->second, testing::bytesOf(p)) << "uid " << p.uid;
  }
  const auto pairs = gatherPairs(read, comm);
  ASSERT_EQ(pairs.size(), truth.keys.size());
  for (std::size_t k = 0; k < truth.keys.size(); ++k) {
    const auto it = pairs.find(truth.keys[k]);
    ASSERT_NE(it, pairs.end());
    EXPECT_EQ(it->second, testing::bytesOf(truth.keys[k], truth.histories[k]));
  }
}

/// A communicator of the first `count` ranks of `comm` (MPI_COMM_NULL on the others).
MPI_Comm firstRanks(MPI_Comm comm, int count) {
  MPI_Comm sub = MPI_COMM_NULL;
  const bool in = mpi::rank(comm) < count;
  MPI_Comm_split(comm, in ? 0 : MPI_UNDEFINED, mpi::rank(comm), &sub);
  return sub;
}

class CheckpointRoundTrip : public ::testing::Test {
 protected:
  void SetUp() override { dir_ = testing::scratchDirectory("checkpoint_rt", MPI_COMM_WORLD); }
  void TearDown() override {
    MPI_Barrier(MPI_COMM_WORLD);
    if (mpi::rank() == 0) std::filesystem::remove_all(dir_);
  }
  std::filesystem::path dir_;
};

TEST_F(CheckpointRoundTrip, SameRankCountGivesEveryFieldBackBitForBit) {
  const Truth truth = makeTruth();
  const int rank = mpi::rank(), ranks = mpi::size();
  const auto path = dir_ / "same.h5";
  writeCheckpoint(path, shareOf(truth, rank, ranks), MPI_COMM_WORLD);
  const sim::CheckpointData read = readCheckpoint(path, MPI_COMM_WORLD);
  expectReplicated(read, truth.replicated);
  expectDistributed(read, truth, MPI_COMM_WORLD);
  // Rank r got slice r: the shares differ by at most one particle / pair.
  const auto mine = static_cast<std::int64_t>(read.particles.size() - truth.globals.size());
  EXPECT_LE(
      mpi::allreduceMax(static_cast<double>(mine)) - mpi::allreduceMin(static_cast<double>(mine)),
      1.0);
}

TEST_F(CheckpointRoundTrip, ReadOnAnotherRankCount) {
  const Truth truth = makeTruth();
  const int rank = mpi::rank(), ranks = mpi::size();
  // Written by all ranks, read by all but one of them (3 of 4: uneven slices).
  const auto all_path = dir_ / "all.h5";
  writeCheckpoint(all_path, shareOf(truth, rank, ranks), MPI_COMM_WORLD);
  const int part = std::max(1, ranks - 1);
  if (MPI_Comm sub = firstRanks(MPI_COMM_WORLD, part); sub != MPI_COMM_NULL) {
    const sim::CheckpointData read = readCheckpoint(all_path, sub);
    expectReplicated(read, truth.replicated);
    expectDistributed(read, truth, sub);
    MPI_Comm_free(&sub);
  }
  // Written by a part of the ranks, read by all.
  const auto part_path = dir_ / "part.h5";
  if (MPI_Comm sub = firstRanks(MPI_COMM_WORLD, part); sub != MPI_COMM_NULL) {
    writeCheckpoint(part_path, shareOf(truth, mpi::rank(sub), part), sub);
    MPI_Comm_free(&sub);
  }
  MPI_Barrier(MPI_COMM_WORLD);
  const sim::CheckpointData read = readCheckpoint(part_path, MPI_COMM_WORLD);
  expectReplicated(read, truth.replicated);
  expectDistributed(read, truth, MPI_COMM_WORLD);
}

TEST_F(CheckpointRoundTrip, SmallTransfersTakeSeveralCollectiveRounds) {
  // 300-byte rounds (2 particle or pair rows): every rank moves each table in many rounds, the
  // ranks with fewer rows taking part with empty selections.
  const Truth truth = makeTruth(31, 45);
  const auto path = dir_ / "rounds.h5";
  hdf5::CheckpointIoOptions small;
  small.round_bytes = 300;
  writeCheckpoint(path, shareOf(truth, mpi::rank(), mpi::size()), MPI_COMM_WORLD, small);
  const sim::CheckpointData read = readCheckpoint(path, MPI_COMM_WORLD, small);
  expectReplicated(read, truth.replicated);
  expectDistributed(read, truth, MPI_COMM_WORLD);
}

TEST_F(CheckpointRoundTrip, LargeTablesInSeveralRoundsAndBlocks) {
  // 1 MiB rounds hold about 7000 pair rows: on few ranks a round spans several 4096-row blocks
  // and the last block of a round is partial.
  const Truth truth = makeTruth(12000, 20000);
  const auto path = dir_ / "large.h5";
  hdf5::CheckpointIoOptions options;
  options.round_bytes = 1 << 20;
  writeCheckpoint(path, shareOf(truth, mpi::rank(), mpi::size()), MPI_COMM_WORLD, options);
  const sim::CheckpointData read = readCheckpoint(path, MPI_COMM_WORLD, options);
  expectDistributed(read, truth, MPI_COMM_WORLD);
  // Read with the default rounds: the same file.
  expectDistributed(readCheckpoint(path, MPI_COMM_WORLD), truth, MPI_COMM_WORLD);
}

TEST_F(CheckpointRoundTrip, EmptyTablesAndNoParticles) {
  Truth truth = makeTruth(0, 0);
  truth.globals.clear();
  truth.replicated.interactions.clear();
  truth.replicated.run_state.clear();
  truth.replicated.scene_toml.clear();
  const auto path = dir_ / "empty.h5";
  writeCheckpoint(path, shareOf(truth, mpi::rank(), mpi::size()), MPI_COMM_WORLD);
  const sim::CheckpointData read = readCheckpoint(path, MPI_COMM_WORLD);
  expectReplicated(read, truth.replicated);
  EXPECT_TRUE(read.particles.empty());
  EXPECT_TRUE(read.pair_keys.empty());
  const CheckpointSummary s = verifyCheckpoint(path, MPI_COMM_WORLD);
  EXPECT_EQ(s.particles, 0);
  EXPECT_EQ(s.pairs, 0);
}

TEST_F(CheckpointRoundTrip, ChecksumsDoNotDependOnTheWritersRankCount) {
  // Contiguous shares keep the truth's row order on any rank count, so the files hold the same
  // bytes in every dataset and must carry the same checksums.
  const Truth truth = makeTruth();
  const auto many = dir_ / "many.h5", one = dir_ / "one.h5";
  writeCheckpoint(many, shareOf(truth, mpi::rank(), mpi::size(), true), MPI_COMM_WORLD);
  if (MPI_Comm sub = firstRanks(MPI_COMM_WORLD, 1); sub != MPI_COMM_NULL) {
    writeCheckpoint(one, shareOf(truth, 0, 1, true), sub);
    MPI_Comm_free(&sub);
  }
  MPI_Barrier(MPI_COMM_WORLD);
  const auto a = verifyCheckpoint(many, MPI_COMM_WORLD);
  const auto b = verifyCheckpoint(one, MPI_COMM_WORLD);
  ASSERT_EQ(a.datasets.size(), b.datasets.size());
  for (std::size_t i = 0; i < a.datasets.size(); ++i) {
    EXPECT_EQ(a.datasets[i].name, b.datasets[i].name);
    EXPECT_EQ(a.datasets[i].dims, b.datasets[i].dims);
    EXPECT_EQ(a.datasets[i].checksum, b.datasets[i].checksum) << a.datasets[i].name;
  }
  EXPECT_EQ(a.writer_ranks, mpi::size());
  EXPECT_EQ(b.writer_ranks, 1);
}

TEST_F(CheckpointRoundTrip, SummaryCountsAndEnergy) {
  const Truth truth = makeTruth(40, 70, false);
  const auto path = dir_ / "summary.h5";
  writeCheckpoint(path, shareOf(truth, mpi::rank(), mpi::size()), MPI_COMM_WORLD);
  const CheckpointSummary s = verifyCheckpoint(path, MPI_COMM_WORLD);
  EXPECT_EQ(s.particles, static_cast<std::int64_t>(truth.free.size() + truth.globals.size()));
  EXPECT_EQ(s.replicated_particles, static_cast<std::int64_t>(truth.globals.size()));
  EXPECT_EQ(s.pairs, static_cast<std::int64_t>(truth.keys.size()));
  std::int64_t touching = 0;
  for (const auto& h : truth.histories) touching += h.touching;
  EXPECT_EQ(s.touching_pairs, touching);
  EXPECT_EQ(s.step, truth.replicated.step);
  EXPECT_EQ(s.scene_hash, hdf5::checksumOfBytes(truth.replicated.scene_toml));
  // Energy of each free particle from its definition: 1/2 m v^2 + 1/2 w . I w.
  ExactSum energy;
  Vec3 lo = Vec3::Constant(1e300), hi = -lo;
  for (const auto& p : truth.free) {
    const auto& shape = truth.replicated.shapes[p.shape];
    const double density = truth.replicated.materials[p.material].density;
    const Mat3 r = p.orientation.toRotationMatrix();
    const Mat3 inertia = r * (density * shape.principal_moments).asDiagonal() * r.transpose();
    const Vec3 w = inertia.inverse() * p.angular_momentum;
    energy.add(0.5 * density * shape.volume * p.velocity.squaredNorm() + 0.5 * w.dot(inertia * w));
  }
  for (const auto& p : truth.free) {
    lo = lo.cwiseMin(p.position);
    hi = hi.cwiseMax(p.position);
  }
  for (const auto& p : truth.globals) {
    lo = lo.cwiseMin(p.position);
    hi = hi.cwiseMax(p.position);
  }
  EXPECT_NEAR(s.kinetic_energy, energy.value(), 1e-12 * energy.value());
  EXPECT_TRUE(sameBits(s.particles_lo, lo));
  EXPECT_TRUE(sameBits(s.particles_hi, hi));
  const std::string text = formatCheckpointSummary(s);
  EXPECT_NE(text.find("step: 4321"), std::string::npos) << text;
  EXPECT_NE(text.find("digest: "), std::string::npos) << text;
  EXPECT_NE(text.find("/particles/position [" + std::to_string(s.particles) + " x 3]"),
            std::string::npos)
      << text;
}

// Writes sample.h5 and what the C++ reader says about it (expected.json) for the Python check
// (tests/checkpoint/checkpoint_summary_test.py); only when POLYDEM_CHECKPOINT_SAMPLE_DIR is set.
TEST(CheckpointSample, WriteForPython) {
  const char* dir = std::getenv("POLYDEM_CHECKPOINT_SAMPLE_DIR");
  if (!dir) GTEST_SKIP() << "POLYDEM_CHECKPOINT_SAMPLE_DIR is not set";
  if (mpi::rank() == 0) std::filesystem::create_directories(dir);
  MPI_Barrier(MPI_COMM_WORLD);
  const std::filesystem::path path = std::filesystem::path(dir) / "sample.h5";
  const Truth truth = makeTruth(300, 700, false, 7);
  writeCheckpoint(path, shareOf(truth, mpi::rank(), mpi::size()), MPI_COMM_WORLD);
  const CheckpointSummary s = verifyCheckpoint(path, MPI_COMM_WORLD);
  if (mpi::rank() != 0) return;
  auto vec = [](const Vec3& v) { return nlohmann::json::array({v.x(), v.y(), v.z()}); };
  nlohmann::json j = {{"step", s.step},
                      {"time", s.time},
                      {"dt", s.dt},
                      {"stage", sim::toString(s.stage)},
                      {"particles", s.particles},
                      {"replicated_particles", s.replicated_particles},
                      {"pairs", s.pairs},
                      {"touching_pairs", s.touching_pairs},
                      {"shapes", s.shapes},
                      {"materials", s.materials},
                      {"writer_ranks", s.writer_ranks},
                      {"scene_hash", BitHasher::hex(s.scene_hash)},
                      {"particles_lo", vec(s.particles_lo)},
                      {"particles_hi", vec(s.particles_hi)},
                      {"kinetic_energy", s.kinetic_energy},
                      {"digest", BitHasher::hex(s.digest)}};
  for (const auto& d : s.datasets) j["datasets"][d.name] = BitHasher::hex(d.checksum);
  std::ofstream(std::filesystem::path(dir) / "expected.json") << j.dump(1) << "\n";
}

TEST(CheckpointShapes, MismatchNamesTheFirstDifference) {
  particles::ShapeTable built;
  built.push_back(testing::bodyShape(
      {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}, {0, 0, 1}, {1, 0, 1}, {0, 1, 1}, {1, 1, 1}},
      "cube"));
  auto stored = sim::shapeRecords(built);
  EXPECT_EQ(sim::shapeMismatch(stored, built), "");
  stored[0].vertices[3].x() = std::nextafter(stored[0].vertices[3].x(), 1.0);
  EXPECT_NE(sim::shapeMismatch(stored, built).find("vertex 3 differs"), std::string::npos);
  stored = sim::shapeRecords(built);
  stored[0].inradius *= 1.0 + 1e-16 * 4;
  EXPECT_NE(sim::shapeMismatch(stored, built).find("mass properties"), std::string::npos);
  stored = sim::shapeRecords(built);
  stored.push_back(stored[0]);
  EXPECT_NE(sim::shapeMismatch(stored, built).find("2 shapes"), std::string::npos);
}

}  // namespace
}  // namespace polydem::checkpoint
