// Block loads with duplicated border pairs: the rank-load formula, the refinement that lowers the
// maximum load, and partitions of forests that are mostly empty.
#include "polydem/domain/block_loads.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <tuple>
#include <vector>

#include "polydem/domain/domain_error.h"

namespace polydem::domain {
namespace {

/// A dense pack as the contact phase sees it: particles on the integer lattice points of
/// [lo, lo + size) (cost 0.5 each) and a pair (cost 1) between every two within distance sqrt(3)
/// (the 26-neighbourhood), binned into the blocks of `forest`.
BlockLoads packLoads(const BlockForest& forest, const Index3& lo, const Index3& size) {
  BlockLoads loads(forest.numBlocks());
  auto at = [&](int i, int j, int k) {
    return Vec3(lo[0] + i + 0.5, lo[1] + j + 0.5, lo[2] + k + 0.5);
  };
  for (int k = 0; k < size[2]; ++k) {
    for (int j = 0; j < size[1]; ++j) {
      for (int i = 0; i < size[0]; ++i) {
        const int b = forest.blockOf(at(i, j, k));
        loads.self[b] += 0.5;
        for (int dz = -1; dz <= 1; ++dz) {
          for (int dy = -1; dy <= 1; ++dy) {
            for (int dx = -1; dx <= 1; ++dx) {
              // each pair once: the partner after this particle in lattice order
              if (std::make_tuple(dz, dy, dx) <= std::make_tuple(0, 0, 0)) continue;
              const int ii = i + dx, jj = j + dy, kk = k + dz;
              if (ii < 0 || jj < 0 || kk < 0 || ii >= size[0] || jj >= size[1] || kk >= size[2]) {
                continue;
              }
              loads.addPair(b, forest.blockOf(at(ii, jj, kk)), 1.0);
            }
          }
        }
      }
    }
  }
  loads.merge();
  return loads;
}

double maxLoad(std::span<const int> map, const BlockLoads& loads, int ranks) {
  const auto l = rankLoads(map, loads, ranks);
  return *std::max_element(l.begin(), l.end());
}

TEST(BlockLoads, RankLoadsCountBorderPairsOnBothRanks) {
  const BlockForest f(Aabb(Vec3::Zero(), Vec3(4, 1, 1)), {4, 1, 1});
  BlockLoads loads(4);
  loads.self = {1, 2, 3, 4};
  loads.addPair(1, 0, 10);  // stored as (0, 1)
  loads.addPair(1, 2, 20);
  loads.addPair(2, 3, 30);
  loads.addPair(1, 2, 5);  // merged with the other (1, 2)
  loads.merge();
  ASSERT_EQ(loads.links.size(), 3u);
  EXPECT_EQ(loads.links[1].weight, 25);
  const std::vector<int> map = {0, 0, 1, 1};
  // rank 0: 1 + 2 + 10 (inside) + 25 (border); rank 1: 3 + 4 + 30 + 25 (border, again)
  EXPECT_EQ(rankLoads(map, loads, 2), (std::vector<double>{38, 62}));
  EXPECT_DOUBLE_EQ(imbalance(map, loads, 2), 62.0 / 50.0);
  // Without duplicates the loads would sum to the work: self plus half of every link.
  const auto half = loads.halfLinkWeights();
  double sum = 0;
  for (double w : half) sum += w;
  EXPECT_EQ(sum, 1 + 2 + 3 + 4 + 10 + 25 + 30);
}

TEST(BlockLoads, RefinementLowersTheMaximumAndNeverRaisesIt) {
  // A 16 x 16 x 8 pack in 8 x 8 x 4 blocks on 16 ranks: with ~1/4 of a rank's pairs on its
  // borders, a partition balanced without duplicates is off by the difference in border length.
  const BlockForest f(Aabb(Vec3::Zero(), Vec3(16, 16, 8)), {8, 8, 4});
  const BlockLoads loads = packLoads(f, {0, 0, 0}, {16, 16, 8});
  for (int ranks : {2, 8, 16}) {
    std::vector<int> map = partitionMetis(f, loads.halfLinkWeights(), ranks);
    const double before = maxLoad(map, loads, ranks);
    const int moves = refineMaxLoad(f, loads, map, ranks);
    const double after = maxLoad(map, loads, ranks);
    EXPECT_LE(after, before) << ranks << " ranks";
    if (moves > 0) {
      EXPECT_LT(after, before);
    }
    for (int r = 0; r < ranks; ++r) EXPECT_NE(std::count(map.begin(), map.end(), r), 0);
    // The whole partition (METIS with the links as edge weights, then refinement).
    const std::vector<int> full = partitionLoads(f, loads, ranks);
    EXPECT_LT(imbalance(full, loads, ranks), 1.10) << ranks << " ranks";
    EXPECT_EQ(partitionLoads(f, loads, ranks), full) << "not deterministic";
  }
}

TEST(BlockLoads, MostlyEmptyForestsArePartitionedAroundTheWork) {
  // A 12 x 12 x 6 pack in a forest of 48 x 48 x 24 blocks: 55,296 blocks, 1 % of them with work.
  const BlockForest f(Aabb(Vec3::Zero(), Vec3(96, 96, 48)), {48, 48, 24});
  const BlockLoads loads = packLoads(f, {40, 44, 20}, {12, 12, 6});
  for (int ranks : {2, 8}) {
    const std::vector<int> map = partitionLoads(f, loads, ranks);
    ASSERT_EQ(static_cast<int>(map.size()), f.numBlocks());
    const auto l = rankLoads(map, loads, ranks);
    for (int r = 0; r < ranks; ++r) EXPECT_GT(l[r], 0) << "rank " << r << " got no work";
    EXPECT_LT(imbalance(map, loads, ranks), 1.10) << ranks << " ranks";
    // Every empty block far from the pile belongs to the rank of the pile's nearest border block:
    // the corner blocks to the ranks of the work box's corners.
    const int far = f.blockIndex({0, 0, 0});
    const int near = f.blockOf(Vec3(40 - 1.5, 44 - 1.5, 20 - 1.5));  // the box's corner block
    EXPECT_EQ(map[far], map[near]);
  }
}

TEST(BlockLoads, BadLoadsAreRefused) {
  const BlockForest f(Aabb(Vec3::Zero(), Vec3(4, 1, 1)), {4, 1, 1});
  BlockLoads loads(4);
  loads.links.push_back({2, 1, 1.0});  // not a < b
  std::vector<int> map = {0, 0, 1, 1};
  EXPECT_THROW(refineMaxLoad(f, loads, map, 2), DomainError);
  EXPECT_THROW(partitionLoads(f, BlockLoads(3), 2), DomainError);
}

}  // namespace
}  // namespace polydem::domain
