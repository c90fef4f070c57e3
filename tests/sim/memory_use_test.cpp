// Simulation::memoryUse on a small dense pack of cubes with sub-contacts: each structure's heap
// stays within a bound computed from the sizes of its elements and the counts of the run (pairs,
// sub-contacts, candidates, particles, vertices), with the growth policy of core/memory.h (a
// quarter more when full) for the tables sized by pairs and sub-contacts, and the library's
// doubling for the per-particle arrays. Doubling the pair tables again, keeping a third copy of
// the ordered pairs, or a second history per rank breaks a bound.
#include <gtest/gtest.h>

#include <algorithm>
#include <map>

#include "generators/pile_scene.h"
#include "polydem/core/logging.h"
#include "polydem/core/memory.h"
#include "polydem/core/mpi_env.h"
#include "polydem/sim/simulation.h"

namespace polydem::sim {
namespace {

struct Counts {
  std::size_t particles = 0, vertices = 0, faces = 0;  // stored: local, fixed and ghosts
  std::size_t pairs = 0, subs = 0, candidates = 0, records = 0;
  void takeMax(const Simulation& sim) {
    const auto& storage = sim.particles();
    std::size_t v = 0, f = 0;
    for (std::size_t i = 0; i < storage.size(); ++i) {
      v += storage.worldVertices(i).size();
      f += storage.worldFaceNormals(i).size();
    }
    particles = std::max(particles, storage.size());
    vertices = std::max(vertices, v);
    faces = std::max(faces, f);
    pairs = std::max(pairs, sim.history().size());
    subs = std::max(subs, sim.history().subKeys().size());
    candidates = std::max(candidates, static_cast<std::size_t>(sim.contactStats().candidates));
    records = std::max(records, sim.contacts().records().size());
  }
};

std::map<std::string, std::uint64_t> byName(const MemoryUse& use) {
  std::map<std::string, std::uint64_t> out;
  for (const auto& item : use) out[item.name] = item.bytes;
  return out;
}

TEST(MemoryUse, DensePackWithinBoundsFromCounts) {
  log::setLevel(log::Level::kWarning);
  PileOptions o;
  o.particles = 512;
  o.shapes = "cubes";
  o.gap = -0.001;  // every face in contact from the first step
  o.layers = 8;
  io::Scene scene = makePileScene(o);
  scene.contact_model = "sub-contacts";
  Simulation sim(scene, MPI_COMM_WORLD);
  Counts n;
  std::map<std::string, std::uint64_t> peak;
  for (int step = 0; step < 10; ++step) {
    sim.step();
    n.takeMax(sim);
    for (const auto& [name, bytes] : byName(sim.memoryUse()))
      peak[name] = std::max(peak[name], bytes);
  }
  ASSERT_GT(n.subs, 3 * n.pairs) << "a dense pack: several sub-contacts per pair";

  // The tables sized by pairs and sub-contacts: at most a quarter (or 64) past the largest count.
  auto grown = [](std::size_t count) { return static_cast<std::uint64_t>(growthFor(count)); };
  // Per-particle arrays grow as the library grows them: at most twice the largest count.
  const std::uint64_t np = 2 * static_cast<std::uint64_t>(n.particles + 1);
  const std::uint64_t pair_bytes =
      sizeof(particles::PairKey) + sizeof(particles::PairHistory) + sizeof(std::size_t);
  const std::uint64_t sub_bytes = sizeof(particles::SubKey) + sizeof(particles::SubHistory);
  // Two tables (last step's and the next), each holding one pair's open slots beyond its
  // sub-contacts: at most the corners of two cube faces.
  EXPECT_LE(peak["history_pairs"], 2 * grown(n.pairs) * pair_bytes);
  EXPECT_LE(peak["history_subs"], 2 * grown(n.subs + 8) * sub_bytes);
  EXPECT_LE(peak["records"], grown(n.records) * sizeof(ContactRecord));
  // The candidates in canonical form and sorted by the higher uid; the uid ranks and counts.
  EXPECT_LE(peak["pair_list"], 2 * grown(n.candidates) * sizeof(OrderedPair) +
                                   np * (sizeof(std::pair<Uid, std::int32_t>) +
                                         sizeof(std::int32_t) + 2 * sizeof(std::size_t)));
  EXPECT_LE(peak["kernel_caches"],
            np * (sizeof(Mat3) + sizeof(Vec3) + sizeof(double) + 2 * sizeof(std::size_t) +
                  2 * sizeof(Vec3) + 1 + sizeof(contact::Body)) +
                2 * (n.vertices + n.faces + 64) * sizeof(Vec3));
  EXPECT_LE(peak["particles"],
            np * (2 * sizeof(particles::Particle) + sizeof(Vec3) + 1 + sizeof(void*) +
                  (2 * sizeof(void*) + sizeof(std::pair<Uid, int>))));
  EXPECT_LE(peak["forces"], np * sizeof(dynamics::ForceAccumulator));
  // One cube shape and the box's floor and walls, whatever the particle count.
  EXPECT_LE(peak["shapes"], 4096u * sim.shapes().size());
}

}  // namespace
}  // namespace polydem::sim
