// Simulation::memoryUse on a small dense pack of cubes with sub-contacts: each structure's heap
// stays within a bound computed from the sizes of its elements and the counts of the run (pairs,
// sub-contacts, candidates, particles, vertices), with the growth policy of core/memory.h (a
// quarter more when full) for the tables sized by pairs and sub-contacts, and the library's
// doubling for the per-particle arrays. The contact history is rebuilt in place: its room is
// bounded by last step's entries plus those that appeared, not by two tables. Doubling the pair
// tables again, keeping a third copy of the ordered pairs, or a second history per rank breaks a
// bound.
#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <set>

#include "generators/pile_scene.h"
#include "polydem/core/logging.h"
#include "polydem/core/memory.h"
#include "polydem/core/mpi_env.h"
#include "polydem/sim/history_chunks.h"
#include "polydem/sim/simulation.h"

namespace polydem::sim {
namespace {

// bench scaling's dense pack of 512 cubes in 8 layers, every face in contact from the first step,
// with sub-contacts.
setup::Setup densePack() {
  PileOptions o;
  o.particles = 512;
  o.shapes = "cubes";
  o.gap = -0.001;
  o.layers = 8;
  setup::Setup scene = makePileScene(o);
  scene.contact_model = "sub-contacts";
  return scene;
}

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
    subs = std::max(subs, sim.history().subCount());
    candidates = std::max(candidates, static_cast<std::size_t>(sim.contactStats().candidates));
    if (sim.contacts().keepsRecords()) {
      records = std::max(records, sim.contacts().records().size());
    }
  }
};

// What the in-place rebuild of the history must hold at once: last step's entries, and those
// the new step writes in front of them beyond the old ones (pairs that appeared, pairs with more
// sub-contacts than before).
struct HistoryNeed {
  std::map<particles::PairKey, std::size_t> last;  // last step's pairs and sub-contact counts
  std::size_t last_subs = 0;
  std::size_t pairs = 0, subs = 0;  // the largest over the steps
  void takeMax(const particles::ContactHistory& h) {
    std::map<particles::PairKey, std::size_t> now;
    std::size_t appeared = 0, more_subs = 0;
    for (std::size_t k = 0; k < h.size(); ++k) {
      const auto [first, end] = h.subsOf(k);
      now[h.keys()[k]] = end - first;
      const auto it = last.find(h.keys()[k]);
      if (it == last.end()) ++appeared;
      const std::size_t before = it == last.end() ? 0 : it->second;
      more_subs += end - first > before ? end - first - before : 0;
    }
    pairs = std::max(pairs, last.size() + appeared);
    subs = std::max(subs, last_subs + more_subs);
    last = std::move(now);
    last_subs = h.subCount();
  }
};

std::map<std::string, std::uint64_t> byName(const MemoryUse& use) {
  std::map<std::string, std::uint64_t> out;
  for (const auto& item : use) out[item.name] = item.bytes;
  return out;
}

TEST(MemoryUse, DensePackWithinBoundsFromCounts) {
  log::setLevel(log::Level::kWarning);
  const setup::Setup scene = densePack();
  Simulation sim(scene, MPI_COMM_WORLD);
  Counts n;
  HistoryNeed need;
  std::map<std::string, std::uint64_t> peak;
  for (int step = 0; step < 10; ++step) {
    sim.step();
    n.takeMax(sim);
    need.takeMax(sim.history());
    for (const auto& [name, bytes] : byName(sim.memoryUse()))
      peak[name] = std::max(peak[name], bytes);
  }
  ASSERT_GT(n.subs, 3 * n.pairs) << "a dense pack: several sub-contacts per pair";

  // The tables sized by pairs and sub-contacts: at most a quarter (or 64) past the largest count.
  auto grown = [](std::size_t count) { return static_cast<std::uint64_t>(growthFor(count)); };
  // Per-particle arrays grow as the library grows them: at most twice the largest count.
  const std::uint64_t np = 2 * static_cast<std::uint64_t>(n.particles + 1);
  const std::uint64_t pair_bytes =
      sizeof(particles::PairKey) + sizeof(particles::PairHistory) + sizeof(std::uint32_t);
  const std::uint64_t sub_bytes = sizeof(particles::SubFeature) + sizeof(particles::SubHistory);
  // One table, rebuilt in place, holding at once last step's entries and the new ones written in
  // front of them, plus one pair's open slots beyond its sub-contacts (at most the corners of two
  // cube faces, also the most a pair's buffer of open slots holds).
  EXPECT_LE(peak["history_pairs"], grown(need.pairs) * pair_bytes);
  EXPECT_LE(peak["history_subs"], grown(need.subs + 8) * sub_bytes + 8 * sub_bytes);
  EXPECT_LT(peak["history_subs"], 2 * n.subs * sub_bytes) << "less than two tables";
  // Records are kept by default: one per evaluated pair, beside its work entry of 12 bytes.
  EXPECT_LE(peak["records"], grown(n.records) * sizeof(ContactRecord));
  EXPECT_LE(sizeof(PairWork), 12u);
  EXPECT_LE(peak["pair_work"], grown(n.records) * sizeof(PairWork));
  // The candidates sorted by the higher uid as storage indices, then in key order with their
  // keys; the uid ranks and counts.
  EXPECT_LE(peak["pair_list"],
            grown(n.candidates) * (sizeof(broadphase::CandidatePair) + sizeof(OrderedPair)) +
                np * (sizeof(std::pair<Uid, std::int32_t>) + sizeof(std::int32_t) +
                      2 * sizeof(std::size_t)));
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

// Without a reader of the full contact records (a run without snapshots, tracked particles or
// contact checks), the contact phase keeps none and holds no room for them; the work entries
// (load model, contact count) are the same, and so are the bits of the run.
TEST(MemoryUse, ContactRecordsOnlyWhenKept) {
  log::setLevel(log::Level::kWarning);
  const setup::Setup scene = densePack();
  Simulation kept(scene, MPI_COMM_WORLD), dropped(scene, MPI_COMM_WORLD);
  for (int step = 0; step < 3; ++step) kept.step();
  dropped.step();
  dropped.keepContactRecords(false);  // after a step with records: their room is given back
  for (int step = 0; step < 2; ++step) dropped.step();
  EXPECT_THROW(dropped.contacts().records(), Error);  // an undeclared reader fails loudly
  EXPECT_EQ(dropped.contacts().memory().records, 0u);
  EXPECT_FALSE(kept.contacts().records().empty());
  const auto& work = dropped.contacts().work();
  ASSERT_EQ(work.size(), kept.contacts().records().size());
  for (std::size_t k = 0; k < work.size(); ++k) {
    const ContactRecord& r = kept.contacts().records()[k];
    EXPECT_EQ(work[k].stored_a, r.stored_a);
    EXPECT_EQ(work[k].stored_b, r.stored_b);
    EXPECT_EQ(work[k].subcontacts, r.subcontacts);
    EXPECT_EQ(work[k].has(PairWork::kTouching), r.touching);
    EXPECT_EQ(work[k].has(PairWork::kAFree), r.a >= 0);
    EXPECT_EQ(work[k].has(PairWork::kBFree), r.b >= 0);
    EXPECT_EQ(work[k].has(PairWork::kALocal), r.a_is_local);
  }
  EXPECT_EQ(dropped.monitors().contacts, kept.monitors().contacts);
  EXPECT_GT(kept.monitors().contacts, 0);
  EXPECT_EQ(dropped.stateHash().combined, kept.stateHash().combined);
  EXPECT_EQ(byName(dropped.memoryUse()).at("records"), 0u);
  EXPECT_GE(byName(kept.memoryUse()).at("records"), work.size() * sizeof(ContactRecord));
}

// A restart routes the pair histories to their owners chunk by chunk and merges each chunk into
// the table in place: what one chunk holds in transit is bounded by the chunk size, not by the
// history's, and the restored table is one table (no copy left over from the merges). The run
// continued from it gives the same bits as the run that never stopped.
TEST(MemoryUse, RestartRoutesHistoriesInBoundedChunks) {
  log::setLevel(log::Level::kWarning);
  const setup::Setup scene = densePack();
  Simulation sim(scene, MPI_COMM_WORLD);
  for (int step = 0; step < 10; ++step) sim.step();
  CheckpointData data = sim.checkpoint("", scene.file, "{}");
  // As a checkpoint is read: every rank holds the replicated particles (written from rank 0).
  if (mpi::rank() != 0) {
    std::vector<particles::Particle> replicated;
    for (std::size_t i = 0; i < sim.particles().localCount(); ++i) {
      if (sim.particles()[i].isGlobal()) replicated.push_back(sim.particles()[i]);
    }
    data.particles.insert(data.particles.begin(), replicated.begin(), replicated.end());
  }
  constexpr std::size_t kRecords = 128;  // per chunk and rank
  SavedHistoryChunks chunks(data, MPI_COMM_WORLD, kRecords);
  Simulation restored(scene, data, chunks, "the captured state", MPI_COMM_WORLD);

  const auto& routing = restored.restoreRouting();
  const std::size_t written = data.pair_keys.size() + data.sub_keys.size();
  EXPECT_GE(static_cast<std::size_t>(routing.chunks), written / kRecords);
  // Per chunk, a rank receives as a directory at most two copies of each of the P chunks'
  // records, and keeps at most as many; each is held at most in four forms at once (sent,
  // received, waiting at the directory, kept), each at most twice its size (buffers and vectors
  // double). A record in transit is a type byte, a member uid, a payload byte and a key and
  // history.
  const std::uint64_t record = 2 + sizeof(Uid) +
                               std::max(sizeof(particles::PairKey) + sizeof(particles::PairHistory),
                                        sizeof(particles::SubKey) + sizeof(particles::SubHistory));
  const std::uint64_t bound = 2 * mpi::size() * kRecords * 4 * 2 * record;
  EXPECT_LE(routing.peak_transit_bytes, bound);
  EXPECT_GT(routing.peak_transit_bytes, 0u);
  // The whole history in transit form, all ranks' (what one chunk of everything would hold).
  const std::uint64_t whole = mpi::allreduceSum(static_cast<std::int64_t>(
      data.pair_keys.size() * (sizeof(particles::PairKey) + sizeof(particles::PairHistory)) +
      data.sub_keys.size() * (sizeof(particles::SubKey) + sizeof(particles::SubHistory))));
  EXPECT_LT(bound, whole) << "the pack's history should be larger than the chunks' bound";

  // One table: at most a quarter (or 64) past its counts.
  const auto& h = restored.history();
  const auto use = byName(restored.memoryUse());
  EXPECT_LE(use.at("history_pairs"),
            growthFor(h.size()) * (sizeof(particles::PairKey) + sizeof(particles::PairHistory) +
                                   sizeof(std::size_t)));
  EXPECT_LE(use.at("history_subs"), growthFor(h.subCount()) * (sizeof(particles::SubFeature) +
                                                               sizeof(particles::SubHistory)));

  for (int step = 0; step < 5; ++step) {
    sim.step();
    restored.step();
  }
  EXPECT_EQ(restored.stateHash().combined, sim.stateHash().combined);
}

}  // namespace
}  // namespace polydem::sim
