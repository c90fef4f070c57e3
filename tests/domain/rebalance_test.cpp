// Collective rank-map computation on 1, 2 and 4 ranks: the same map everywhere, equal to the
// pure partition of the summed weights, and errors raised on every rank instead of a hang.
#include "polydem/domain/rebalance.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "polydem/core/mpi_env.h"
#include "polydem/domain/domain_error.h"
#include "polydem/domain/partition.h"

namespace polydem::domain {
namespace {

const Aabb kBox(Vec3(-2, 0, 0), Vec3(2, 3, 1));

/// A load concentrated at `corner` (0 or 1 along every axis), in whole particles per block.
std::vector<double> cornerLoad(const BlockForest& f, int corner) {
  std::vector<double> w(f.numBlocks());
  for (int b = 0; b < f.numBlocks(); ++b) {
    const Index3 c = f.blockCoords(b);
    double d = 0;
    for (int a = 0; a < 3; ++a) d += corner ? f.counts()[a] - 1 - c[a] : c[a];
    w[b] = std::floor(200.0 * std::exp(-0.7 * d));
  }
  return w;
}

/// This rank's share: the weights of the blocks it owns under the forest's current map, or of
/// every size-th block while the forest still has its initial one-rank map.
std::vector<double> localShare(const BlockForest& f, const std::vector<double>& global) {
  std::vector<double> local(global.size(), 0.0);
  const int me = mpi::rank();
  const bool mapped = f.numRanks() == mpi::size();
  for (int b = 0; b < f.numBlocks(); ++b) {
    if (mapped ? f.rankOfBlock(b) == me : b % mpi::size() == me) local[b] = global[b];
  }
  return local;
}

bool sameOnAllRanks(const std::vector<int>& map) {
  const std::vector<int> all = mpi::allgatherv(map);
  for (std::size_t i = 0; i < all.size(); ++i) {
    if (all[i] != map[i % map.size()]) return false;
  }
  return true;
}

TEST(ComputeRankMap, SameMapOnEveryRankAndEqualToThePurePartition) {
  const int ranks = mpi::size();
  const BlockForest f(kBox, chooseBlockCounts(kBox, ranks, 8));
  const std::vector<double> global = cornerLoad(f, 0);
  for (PartitionMethod method : {PartitionMethod::kMetis, PartitionMethod::kSfc}) {
    const std::vector<int> map = computeRankMap(f, localShare(f, global), MPI_COMM_WORLD, method);
    EXPECT_TRUE(sameOnAllRanks(map));
    std::vector<int> pure = method == PartitionMethod::kMetis ? partitionMetis(f, global, ranks)
                                                              : partitionSfc(f, global, ranks);
    if (f.numRanks() == ranks) pure = relabelToMatch(f, pure, f.rankMap(), global, ranks);
    EXPECT_EQ(map, pure);
  }
}

TEST(Rebalance, FollowsAMovingLoadAndKeepsAStableMap) {
  const int ranks = mpi::size();
  BlockForest f(kBox, chooseBlockCounts(kBox, ranks, 8));
  const std::vector<double> start = cornerLoad(f, 0);
  const RebalanceReport first = rebalance(f, localShare(f, start));
  EXPECT_EQ(f.numRanks(), ranks);
  EXPECT_TRUE(sameOnAllRanks(f.rankMap()));
  for (int r = 0; r < ranks; ++r) EXPECT_FALSE(f.blocksOfRank(r).empty());
  EXPECT_DOUBLE_EQ(first.imbalance_after, imbalance(f.rankMap(), start, ranks));
  EXPECT_EQ(first.imbalance_before, 1.0);  // the initial map has one rank

  // Same load again: the same partition, under the same rank names -> nothing moves.
  const std::vector<int> settled = f.rankMap();
  const RebalanceReport again = rebalance(f, localShare(f, start));
  EXPECT_EQ(again.blocks_moved, 0);
  EXPECT_EQ(f.rankMap(), settled);
  EXPECT_DOUBLE_EQ(again.imbalance_before, again.imbalance_after);

  // The load runs out to the opposite corner: the old map is now unbalanced, the new one is not
  // worse than a METIS partition of that load (it is one).
  const std::vector<double> runout = cornerLoad(f, 1);
  const double stale = imbalance(f.rankMap(), runout, ranks);
  const RebalanceReport moved = rebalance(f, localShare(f, runout));
  EXPECT_DOUBLE_EQ(moved.imbalance_before, stale);
  EXPECT_DOUBLE_EQ(moved.imbalance_after,
                   imbalance(partitionMetis(f, runout, ranks), runout, ranks));
  if (ranks > 1) {
    EXPECT_LT(moved.imbalance_after, moved.imbalance_before);
    EXPECT_GT(moved.blocks_moved, 0);
  }
  EXPECT_TRUE(sameOnAllRanks(f.rankMap()));
}

TEST(ComputeRankMap, ErrorsReachEveryRank) {
  const int ranks = mpi::size();
  const BlockForest f(kBox, chooseBlockCounts(kBox, ranks, 2));
  // a bad weight on the last rank only
  std::vector<double> local(f.numBlocks(), 1.0);
  if (mpi::rank() == ranks - 1) local[1] = -1.0;
  EXPECT_THROW(computeRankMap(f, local), DomainError);
  // a wrong length on rank 0 only
  std::vector<double> short_local(f.numBlocks() - (mpi::rank() == 0 ? 1 : 0), 1.0);
  EXPECT_THROW(computeRankMap(f, short_local), DomainError);
  // more ranks than blocks: rank 0's partitioner throws, every rank gets the error
  if (ranks > 1) {
    const BlockForest tiny(kBox, {1, 1, 1});
    EXPECT_THROW(computeRankMap(tiny, std::vector<double>(1, 1.0)), DomainError);
  }
  // and the communicator is still usable afterwards
  const std::vector<int> map = computeRankMap(f, std::vector<double>(f.numBlocks(), 1.0));
  EXPECT_TRUE(sameOnAllRanks(map));
}

/// Block loads of a lump of work: self weights cornerLoad(corner) and a link of a tenth of the
/// smaller self weight between every two face neighbours, split over the ranks by block index.
BlockLoads lumpLoads(const BlockForest& f, int corner, bool mine_only) {
  const std::vector<double> w = cornerLoad(f, corner);
  BlockLoads loads(f.numBlocks());
  for (int b = 0; b < f.numBlocks(); ++b) {
    if (mine_only && b % mpi::size() != mpi::rank()) continue;
    loads.self[b] = w[b];
    for (int a = 0; a < 3; ++a) {
      Index3 step{0, 0, 0};
      step[a] = 1;
      const int n = f.neighbourIndex(b, step);
      if (n > b) loads.addPair(b, n, 0.1 * std::min(w[b], w[n]));
    }
  }
  loads.merge();
  return loads;
}

TEST(ProposeBalance, AdoptsOnlyWhatIsBetterByTheMargin) {
  const int ranks = mpi::size();
  BlockForest f(kBox, chooseBlockCounts(kBox, ranks, 8));
  const BlockLoads lump = lumpLoads(f, 0, true), whole = lumpLoads(f, 0, false);
  f.setRankMap(computeRankMap(f, lump), ranks);
  EXPECT_TRUE(sameOnAllRanks(f.rankMap()));
  // The same work again: nothing better by 2 % exists, so the map stays.
  const BalanceProposal again =
      proposeBalance(f, lump, nullptr, nullptr, MPI_COMM_WORLD, PartitionMethod::kMetis, 0.02);
  EXPECT_DOUBLE_EQ(again.imbalance_before, imbalance(f.rankMap(), whole, ranks));
  EXPECT_FALSE(again.adopted);
  // Even with no margin, a proposal that is worse is never adopted.
  const BalanceProposal strict =
      proposeBalance(f, lump, nullptr, nullptr, MPI_COMM_WORLD, PartitionMethod::kMetis, 0.0);
  EXPECT_EQ(strict.adopted, strict.imbalance_after <= strict.imbalance_before);
  // The work moves to the opposite corner: the new map is adopted, the same on every rank.
  const BlockLoads moved = lumpLoads(f, 1, true);
  const BalanceProposal p =
      proposeBalance(f, moved, nullptr, nullptr, MPI_COMM_WORLD, PartitionMethod::kMetis, 0.02);
  EXPECT_TRUE(sameOnAllRanks(p.map));
  if (ranks > 1) {
    EXPECT_TRUE(p.adopted);
    EXPECT_LE(p.imbalance_after * 1.02, p.imbalance_before);
    EXPECT_GT(p.blocks_moved, 0);
    EXPECT_DOUBLE_EQ(p.imbalance_after, imbalance(p.map, lumpLoads(f, 1, false), ranks));
  }
  // A candidate forest of other block counts over the same domain.
  const BlockForest finer(kBox, chooseBlockCounts(kBox, ranks, 16));
  const BlockLoads on_finer = lumpLoads(finer, 1, true);
  const BalanceProposal q =
      proposeBalance(f, moved, &finer, &on_finer, MPI_COMM_WORLD, PartitionMethod::kSfc, 0.02);
  EXPECT_EQ(static_cast<int>(q.map.size()), finer.numBlocks());
  EXPECT_EQ(q.blocks_moved, -1);
  EXPECT_TRUE(sameOnAllRanks(q.map));
  EXPECT_EQ(q.adopted, q.imbalance_after * 1.02 <= q.imbalance_before);
  // A candidate over another domain is refused on every rank.
  const BlockForest other(Aabb(Vec3::Zero(), Vec3::Ones()), {2, 2, 2});
  EXPECT_THROW(
      proposeBalance(f, moved, &other, &on_finer, MPI_COMM_WORLD, PartitionMethod::kMetis, 0.02),
      DomainError);
}

}  // namespace
}  // namespace polydem::domain
