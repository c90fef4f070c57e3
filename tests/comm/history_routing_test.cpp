// routeHistories: pair histories read as arbitrary slices reach exactly the ranks owning one of
// their particles, bit for bit, once each; replicated particles are everywhere.
#include "polydem/comm/history_routing.h"

#include <gtest/gtest.h>

#include <map>
#include <set>

#include "polydem/core/error.h"
#include "polydem/core/mpi_env.h"

namespace polydem::comm {
namespace {

using particles::PairHistory;
using particles::PairKey;

constexpr Uid kFirstReplicated = 1000;

/// The world of the test: free uids 1..n owned by ownerOf(uid), two replicated uids, and pairs of
/// free-free, free-replicated and replicated-replicated particles.
struct World {
  int ranks = 1;
  std::vector<Uid> free, replicated{kFirstReplicated, kFirstReplicated + 1};
  std::vector<PairKey> keys;
  std::vector<PairHistory> histories;

  int ownerOf(Uid u) const { return static_cast<int>((u * 7 + 3) % static_cast<Uid>(ranks)); }
  bool isReplicated(Uid u) const { return u >= kFirstReplicated; }
};

PairHistory historyOf(const PairKey& k) {
  PairHistory h;
  const double a = static_cast<double>(k.lo), b = static_cast<double>(k.hi);
  h.shear_force = Vec3(a, -b, a * b);
  h.normal = Vec3(1.0 / a, 1.0 / b, -0.0);
  h.kernel.warm_direction = Vec3(a + 0.5, b, 3);
  h.kernel.warm_point = Vec3(-a, b * 1e-300, 7);
  h.kernel.warm_valid = static_cast<std::uint32_t>(k.lo % 2);
  h.kernel.reserved = static_cast<std::uint32_t>(k.hi);
  h.touching = static_cast<std::uint32_t>((k.lo + k.hi) % 2);
  return h;
}

World makeWorld(int ranks, Uid n = 41) {
  World w;
  w.ranks = ranks;
  for (Uid u = 1; u <= n; ++u) w.free.push_back(u);
  std::set<PairKey> keys;
  for (Uid a = 1; a <= n; ++a) {
    for (Uid d : {1u, 3u, 17u}) {
      if (a + d <= n) keys.insert({a, a + d});
    }
    if (a % 4 == 0) keys.insert({a, kFirstReplicated + a % 2});
  }
  keys.insert({kFirstReplicated, kFirstReplicated + 1});
  for (const auto& k : keys) {
    w.keys.push_back(k);
    w.histories.push_back(historyOf(k));
  }
  return w;
}

/// The slice rank `rank` "read": an arbitrary interleaved share, not related to ownership.
void sliceOf(const World& w, int rank, std::vector<PairKey>& keys,
             std::vector<PairHistory>& histories) {
  for (std::size_t i = 0; i < w.keys.size(); ++i) {
    if (static_cast<int>((i * 5 + 1) % static_cast<std::size_t>(w.ranks)) == rank) {
      keys.push_back(w.keys[i]);
      histories.push_back(w.histories[i]);
    }
  }
}

std::vector<Uid> ownedBy(const World& w, int rank) {
  std::vector<Uid> out;
  for (Uid u : w.free) {
    if (w.ownerOf(u) == rank) out.push_back(u);
  }
  return out;
}

/// A history's fields as bytes (the wire format): equal bytes = equal bits, padding left out.
std::vector<std::byte> bytesOf(const PairKey& k, const PairHistory& h) {
  SendBuffer b;
  particles::pack(b, k, h);
  return b.bytes();
}

/// The routed history of `rank` is exactly the pairs with a particle owned by `rank` (a pair of
/// two replicated particles on every rank), sorted, bit for bit.
void expectDelivered(const World& w, int rank, const particles::ContactHistory& got) {
  std::vector<PairKey> expected;
  for (const auto& k : w.keys) {
    const bool mine = (!w.isReplicated(k.lo) && w.ownerOf(k.lo) == rank) ||
                      (!w.isReplicated(k.hi) && w.ownerOf(k.hi) == rank) ||
                      (w.isReplicated(k.lo) && w.isReplicated(k.hi));
    if (mine) expected.push_back(k);
  }
  ASSERT_EQ(got.size(), expected.size());
  for (std::size_t i = 0; i < expected.size(); ++i) {
    EXPECT_EQ(got.keys()[i], expected[i]);
    EXPECT_EQ(bytesOf(expected[i], got.entries()[i]), bytesOf(expected[i], historyOf(expected[i])))
        << "pair (" << expected[i].lo << ", " << expected[i].hi << ")";
  }
}

TEST(HistoryRouting, EachPairReachesTheOwnersOfItsParticles) {
  const int rank = mpi::rank(), ranks = mpi::size();
  const World w = makeWorld(ranks);
  std::vector<PairKey> keys;
  std::vector<PairHistory> histories;
  sliceOf(w, rank, keys, histories);
  HistoryRoutingStats stats;
  const auto owned = ownedBy(w, rank);
  const auto got = routeHistories(keys, histories, owned, w.replicated, MPI_COMM_WORLD, &stats);
  expectDelivered(w, rank, got);
  EXPECT_EQ(stats.registered, static_cast<std::int64_t>(owned.size()));
  EXPECT_EQ(stats.kept, static_cast<std::int64_t>(got.size()));
  // Every pair with a free particle was forwarded once per free particle.
  std::int64_t expected_forwards = 0;
  for (const auto& k : w.keys) expected_forwards += !w.isReplicated(k.lo) + !w.isReplicated(k.hi);
  EXPECT_EQ(mpi::allreduceSum(stats.forwarded), expected_forwards);
}

TEST(HistoryRouting, AllHistoriesOnOneRankOrNone) {
  const int rank = mpi::rank(), ranks = mpi::size();
  const World w = makeWorld(ranks);
  const bool last = rank == ranks - 1;
  const auto got = routeHistories(
      last ? std::span<const PairKey>(w.keys) : std::span<const PairKey>(),
      last ? std::span<const PairHistory>(w.histories) : std::span<const PairHistory>(),
      ownedBy(w, rank), w.replicated, MPI_COMM_WORLD);
  expectDelivered(w, rank, got);
}

TEST(HistoryRouting, FromParticleStorage) {
  const int rank = mpi::rank(), ranks = mpi::size();
  const World w = makeWorld(ranks);
  particles::ParticleStorage storage;
  for (Uid u : w.replicated) {
    particles::Particle p;
    p.uid = u;
    p.flags = particles::kFixed;
    storage.addLocal(p);
  }
  for (Uid u : ownedBy(w, rank)) {
    particles::Particle p;
    p.uid = u;
    storage.addLocal(p);
  }
  std::vector<PairKey> keys;
  std::vector<PairHistory> histories;
  sliceOf(w, rank, keys, histories);
  expectDelivered(w, rank, routeHistories(keys, histories, storage, MPI_COMM_WORLD));
}

TEST(HistoryRouting, APairWithAParticleNobodyOwnsFailsEverywhere) {
  const int rank = mpi::rank(), ranks = mpi::size();
  const World w = makeWorld(ranks);
  std::vector<PairKey> keys;
  std::vector<PairHistory> histories;
  if (rank == 0) {
    keys.push_back({5, 777});
    histories.push_back(historyOf(keys.back()));
  }
  try {
    routeHistories(keys, histories, ownedBy(w, rank), w.replicated, MPI_COMM_WORLD);
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("particle uid 777"), std::string::npos) << e.what();
  }
}

TEST(HistoryRouting, AUidOwnedTwiceFailsEverywhere) {
  const int rank = mpi::rank(), ranks = mpi::size();
  const World w = makeWorld(ranks);
  auto owned = ownedBy(w, rank);
  if (rank == 0) owned.push_back(w.free.back());  // twice on rank 0, or on rank 0 and its owner
  EXPECT_THROW(routeHistories({}, {}, owned, w.replicated, MPI_COMM_WORLD), Error);
}

}  // namespace
}  // namespace polydem::comm
