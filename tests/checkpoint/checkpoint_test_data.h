// Checkpoint contents for the tests: a global "truth" (replicated tables, every particle and pair
// history) with awkward bit patterns (-0, subnormals, huge values, odd quaternions), and the share
// of it a given rank of a given rank count passes to writeCheckpoint.
#pragma once

#include <gtest/gtest.h>
#include <mpi.h>
#include <unistd.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "polydem/checkpoint/checkpoint.h"
#include "polydem/core/byte_buffer.h"
#include "polydem/core/mpi_env.h"
#include "polydem/geometry/body_shape.h"

namespace polydem::checkpoint::testing {

/// Deterministic doubles; `awkward`: with every kind of bit pattern a state can hold.
class Values {
 public:
  Values(std::uint64_t seed, bool awkward)
      : state_(seed * 0x9e3779b97f4a7c15ULL + 1), awkward_(awkward) {}
  double next() {
    state_ = state_ * 6364136223846793005ULL + 1442695040888963407ULL;
    const std::uint64_t r = state_ >> 11;
    switch (awkward_ ? r % 11 : 10) {
      case 0:
        return -0.0;
      case 1:
        return 4.9e-324 * static_cast<double>(r % 7 + 1);  // subnormal
      case 2:
        return 1.5e308 * ((r & 1) ? -1.0 : 1.0);
      default:
        return (static_cast<double>(r) / 9007199254740992.0 - 0.5) * 10.0;
    }
  }
  Vec3 vec3() { return {next(), next(), next()}; }

 private:
  std::uint64_t state_;
  bool awkward_;
};

struct Truth {
  sim::CheckpointData replicated;  // everything but particles and pair histories
  std::vector<particles::Particle> globals, free;
  std::vector<particles::PairKey> keys;
  std::vector<particles::PairHistory> histories;
};

inline geometry::BodyShape bodyShape(const std::vector<Vec3>& points, const std::string& name) {
  return geometry::toBodyFrame(geometry::ConvexPolyhedron::fromPoints(points), name).shape;
}

/// `awkward`: bit patterns no physical state has (huge values, quaternions that are not
/// rotations), for round trips; otherwise a state whose energy can be computed.
inline Truth makeTruth(int free_count = 57, int pair_count = 83, bool awkward = true,
                       std::uint64_t seed = 1) {
  Truth t;
  sim::CheckpointData& d = t.replicated;
  d.code_version = "0.1.0-test";
  d.scene_file = "scenes/test.toml";
  d.scene_toml = "# test scene\nid = \"T\"\n[[material]]\nname = \"rock\"\n";
  // As a time loop leaves them: time = step x dt exactly, the sum of `step` time steps.
  d.step = 4321;
  d.dt = 1.1e-4;
  ExactSum time;
  for (int i = 0; i < d.step; ++i) time.add(d.dt);
  d.time_digits = time.digits();
  d.time = time.value();
  d.stage = sim::CheckpointStage::kEquilibrium;
  d.equilibrium_steps = 4321;
  d.equilibrium_reached = true;
  d.run_state = R"({"checks": {"drop": [1, 2.5]}, "tracker": null})";
  particles::ShapeTable shapes;
  shapes.push_back(bodyShape(
      {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}, {0, 0, 1}, {1, 0, 1}, {0, 1, 1}, {1, 1, 1}},
      "cube"));
  shapes.push_back(bodyShape({{0, 0, 0}, {2, 0.1, 0}, {0.3, 1.7, 0.2}, {0.4, 0.5, 1.3}}, "tet"));
  d.shapes = sim::shapeRecords(shapes);
  d.materials.push_back({"rock", 2650, 1e9, 5e8, 30, 0, 0.1, 0.0, 1e8});
  d.materials.push_back({"concrete-with-a-long-name", 2400.5, 2e9, 1e9, 35.5, 12.0, 0.2, 0.8, 0});
  d.interactions.push_back({0, 1, {3e9, 2e9, 25, 1.5, 0.05, 7e7}});
  d.domain.lo = Vec3(-1, -2.5, 0);
  d.domain.hi = Vec3(10, 2.5, 7.75);
  d.domain.blocks = {3, 2, 1};
  d.domain.periodic = {false, true, false};
  d.domain.rank_map = {0, 1, 1, 0, 2, 2};
  d.domain.ranks = 3;

  Values v(seed, awkward);
  for (int i = 0; i < 3; ++i) {  // a fixed base, a driven platform, another fixed block
    particles::Particle p;
    p.uid = 1000000 + static_cast<Uid>(i);
    p.shape = i % 2;
    p.material = 1;
    p.flags = i == 1 ? particles::kDriven : particles::kFixed;
    p.driver = i == 1 ? 0 : -1;
    p.position = v.vec3();
    p.orientation = Quat(0.5, -0.5, 0.5, -0.5);
    p.velocity = i == 1 ? v.vec3() : Vec3::Zero();
    t.globals.push_back(p);
  }
  for (int i = 0; i < free_count; ++i) {
    particles::Particle p;
    p.uid = 7 + 3 * static_cast<Uid>(i) + (static_cast<Uid>(i) << 40);
    p.shape = i % 2;
    p.material = (i / 2) % 2;
    p.position = v.vec3();
    p.orientation = Quat(v.next(), v.next(), v.next(), v.next());
    if (!awkward) p.orientation.normalize();
    p.velocity = v.vec3();
    p.angular_momentum = v.vec3();
    t.free.push_back(p);
  }
  for (int k = 0; k < pair_count; ++k) {
    const Uid a = t.free[static_cast<std::size_t>(k) % t.free.size()].uid;
    const Uid b = k % 5 == 0 ? t.globals[static_cast<std::size_t>(k) % 3].uid
                             : t.free[(static_cast<std::size_t>(k) * 7 + 1) % t.free.size()].uid;
    if (a == b) continue;
    particles::PairHistory h;
    h.shear_force = v.vec3();
    h.normal = v.vec3();
    h.kernel.warm_direction = v.vec3();
    h.kernel.warm_point = v.vec3();
    h.kernel.warm_valid = static_cast<std::uint32_t>(k % 2);
    h.kernel.reserved = 0xdeadbeefu ^ static_cast<std::uint32_t>(k);
    h.touching = static_cast<std::uint32_t>(k % 3 == 0);
    t.keys.push_back(particles::makeKey(a, b));
    t.histories.push_back(h);
  }
  // Each pair once: drop duplicate keys (keep the first).
  std::vector<particles::PairKey> keys;
  std::vector<particles::PairHistory> histories;
  for (std::size_t i = 0; i < t.keys.size(); ++i) {
    if (std::find(keys.begin(), keys.end(), t.keys[i]) != keys.end()) continue;
    keys.push_back(t.keys[i]);
    histories.push_back(t.histories[i]);
  }
  t.keys = keys;
  t.histories = histories;
  return t;
}

/// What rank `rank` of `ranks` passes to writeCheckpoint: every replicated particle (as the
/// simulation holds them) and an uneven, interleaved share of the free particles and pairs.
/// `contiguous`: rank r holds a contiguous block instead, so that the file's row order is the
/// truth's order whatever the rank count.
inline sim::CheckpointData shareOf(const Truth& t, int rank, int ranks, bool contiguous = false) {
  sim::CheckpointData d = t.replicated;
  auto owner = [&](std::size_t i, std::size_t n) {
    if (contiguous) return static_cast<int>(i * static_cast<std::size_t>(ranks) / n);
    return static_cast<int>((i * i + 3 * i + 1) % static_cast<std::size_t>(ranks));
  };
  // Replicated particles are held by every rank, interleaved with the free ones.
  for (std::size_t i = 0; i < std::max(t.free.size(), t.globals.size()); ++i) {
    if (i < t.globals.size()) d.particles.push_back(t.globals[i]);
    if (i < t.free.size() && owner(i, t.free.size()) == rank) d.particles.push_back(t.free[i]);
  }
  for (std::size_t k = 0; k < t.keys.size(); ++k) {
    if (owner(k, t.keys.size()) == rank) {
      d.pair_keys.push_back(t.keys[k]);
      d.pair_histories.push_back(t.histories[k]);
    }
  }
  return d;
}

/// The bytes of a particle (ParticleExchange's wire format): equal bytes = equal bits.
inline std::vector<std::byte> bytesOf(const particles::Particle& p) {
  SendBuffer b;
  particles::pack(b, p);
  return b.bytes();
}
inline std::vector<std::byte> bytesOf(const particles::PairKey& k,
                                      const particles::PairHistory& h) {
  SendBuffer b;
  particles::pack(b, k, h);
  return b.bytes();
}

/// Free particles of all ranks of `comm`, by uid, as bytes (collective).
inline std::map<Uid, std::vector<std::byte>> gatherFree(const sim::CheckpointData& d,
                                                        MPI_Comm comm) {
  SendBuffer mine;
  for (const auto& p : d.particles) {
    if (!p.isGlobal()) particles::pack(mine, p);
  }
  const auto all = mpi::allgatherv(mine.bytes(), comm);
  std::map<Uid, std::vector<std::byte>> out;
  RecvBuffer in(all.data(), all.size());
  while (!in.atEnd()) {
    particles::Particle p;
    particles::unpack(in, p);
    EXPECT_TRUE(out.emplace(p.uid, bytesOf(p)).second) << "uid " << p.uid << " read twice";
  }
  return out;
}

/// Pair histories of all ranks of `comm`, by key, as bytes (collective).
inline std::map<particles::PairKey, std::vector<std::byte>> gatherPairs(
    const sim::CheckpointData& d, MPI_Comm comm) {
  SendBuffer mine;
  for (std::size_t i = 0; i < d.pair_keys.size(); ++i) {
    particles::pack(mine, d.pair_keys[i], d.pair_histories[i]);
  }
  const auto all = mpi::allgatherv(mine.bytes(), comm);
  std::map<particles::PairKey, std::vector<std::byte>> out;
  RecvBuffer in(all.data(), all.size());
  while (!in.atEnd()) {
    particles::PairKey k;
    particles::PairHistory h;
    particles::unpack(in, k, h);
    EXPECT_TRUE(out.emplace(k, bytesOf(k, h)).second) << "pair read twice";
  }
  return out;
}

/// A fresh directory for this test, the same path on every rank of `comm` (collective).
inline std::filesystem::path scratchDirectory(const std::string& name, MPI_Comm comm) {
  std::string path;
  if (mpi::rank(comm) == 0) {
    path = (std::filesystem::temp_directory_path() /
            ("polydem_" + name + "_" + std::to_string(::getpid())))
               .string();
    std::filesystem::remove_all(path);
    std::filesystem::create_directories(path);
  }
  std::uint64_t n = path.size();
  MPI_Bcast(&n, 1, MPI_UINT64_T, 0, comm);
  path.resize(n);
  MPI_Bcast(path.data(), static_cast<int>(n), MPI_CHAR, 0, comm);
  return path;
}

/// A file's bytes ("" if it cannot be read or is not a regular file, which opening could block),
/// to check that a failed operation left it alone.
inline std::string readBytes(const std::filesystem::path& path) {
  if (!std::filesystem::is_regular_file(path)) return "";
  std::ifstream in(path, std::ios::binary);
  std::ostringstream out;
  out << in.rdbuf();
  return out.str();
}

/// Replaces a file's bytes (to damage a checkpoint on purpose).
inline void writeBytes(const std::filesystem::path& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out << bytes;
}

}  // namespace polydem::checkpoint::testing
