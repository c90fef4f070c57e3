#include "polydem/domain/partition.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <random>
#include <vector>

#include "polydem/domain/domain_error.h"

namespace polydem::domain {
namespace {

const Aabb kUnit(Vec3::Zero(), Vec3::Ones());

void expectValidMap(const std::vector<int>& map, const BlockForest& f, int ranks) {
  ASSERT_EQ(static_cast<int>(map.size()), f.numBlocks());
  std::vector<int> count(ranks, 0);
  for (int r : map) {
    ASSERT_GE(r, 0);
    ASSERT_LT(r, ranks);
    ++count[r];
  }
  for (int r = 0; r < ranks; ++r) EXPECT_GT(count[r], 0) << "rank " << r << " has no block";
}

/// The naive split: equal numbers of blocks in block-index order.
std::vector<int> equalCountSplit(int blocks, int ranks) {
  std::vector<int> map(blocks);
  for (int b = 0; b < blocks; ++b) map[b] = static_cast<int>(static_cast<long>(b) * ranks / blocks);
  return map;
}

TEST(VertexWeights, ScalingAndFloor) {
  const BlockForest f(kUnit, {4, 1, 1});
  EXPECT_EQ(vertexWeights(f, std::vector<double>{0, 1, 2, 4}),
            (std::vector<int>{1, 1 + kWeightResolution / 4, 1 + kWeightResolution / 2,
                              1 + kWeightResolution}));
  EXPECT_EQ(vertexWeights(f, std::vector<double>(4, 0.0)), std::vector<int>(4, 1));
  // only ratios matter
  EXPECT_EQ(vertexWeights(f, std::vector<double>{0, 1e-30, 2e-30, 4e-30}),
            vertexWeights(f, std::vector<double>{0, 1e30, 2e30, 4e30}));
  EXPECT_THROW(vertexWeights(f, std::vector<double>{0, 1, 2}), DomainError);
  EXPECT_THROW(vertexWeights(f, std::vector<double>{0, -1, 2, 3}), DomainError);
  EXPECT_THROW(vertexWeights(f, std::vector<double>{0, NAN, 2, 3}), DomainError);
}

TEST(CapHeavyBlocks, WaterFillingToTheFairShare) {
  // one block outweighs the fair share of 3 ranks: capped at the share of the other 6 on 2 ranks
  EXPECT_EQ(capHeavyBlocks(std::vector<int>{1, 100, 1, 1, 1, 1, 1}, 3),
            (std::vector<int>{1, 3, 1, 1, 1, 1, 1}));
  // two heavy blocks on 4 ranks: 98/4 < 50, then 48/3 < 40, then the 8 light ones on 2 ranks: 4
  std::vector<int> two{50, 40, 1, 1, 1, 1, 1, 1, 1, 1};
  EXPECT_EQ(capHeavyBlocks(two, 4), (std::vector<int>{4, 4, 1, 1, 1, 1, 1, 1, 1, 1}));
  // a feasible load is left alone
  EXPECT_EQ(capHeavyBlocks(std::vector<int>{5, 3, 4, 4}, 2), (std::vector<int>{5, 3, 4, 4}));
  EXPECT_EQ(capHeavyBlocks(std::vector<int>{9, 1}, 1), (std::vector<int>{9, 1}));
}

TEST(BlockGraph, SymmetricWithFaceEdgeCornerWeights) {
  const BlockForest f(kUnit, {3, 3, 3});
  const BlockGraph g = blockGraph(f);
  const int centre = f.blockIndex({1, 1, 1});
  const int total = std::accumulate(g.edge_weights.begin() + g.offsets[centre],
                                    g.edge_weights.begin() + g.offsets[centre + 1], 0);
  EXPECT_EQ(total, 6 * 4 + 12 * 2 + 8 * 1);
  for (int u = 0; u < f.numBlocks(); ++u) {
    const std::vector<int> nbs(g.adjacency.begin() + g.offsets[u],
                               g.adjacency.begin() + g.offsets[u + 1]);
    EXPECT_EQ(nbs, f.neighbours(u));
    for (int k = g.offsets[u]; k < g.offsets[u + 1]; ++k) {
      const int v = g.adjacency[k];
      const auto it =
          std::find(g.adjacency.begin() + g.offsets[v], g.adjacency.begin() + g.offsets[v + 1], u);
      EXPECT_EQ(g.edge_weights[it - g.adjacency.begin()], g.edge_weights[k]);
    }
  }
  // two blocks along a periodic axis touch through both faces
  const BlockForest ring(kUnit, {2, 1, 1}, {true, false, false});
  const BlockGraph gr = blockGraph(ring);
  EXPECT_EQ(gr.adjacency, (std::vector<int>{1, 0}));
  EXPECT_EQ(gr.edge_weights, (std::vector<int>{8, 8}));
  EXPECT_EQ(edgeCut(gr, std::vector<int>{0, 1}), 8);
  EXPECT_EQ(edgeCut(gr, std::vector<int>{1, 1}), 0);
  // Cutting the x = 0 layer off a 3x3x3 forest crosses 9 faces, 24 edges (each layer block has
  // as many edge partners beyond the cut as it has y and z neighbours: 2 * 12) and 16 corners
  // (products of the y and z neighbour counts: 4 * 4): 9*4 + 24*2 + 16*1 = 100.
  std::vector<int> layer(27);
  for (int b = 0; b < 27; ++b) layer[b] = f.blockCoords(b)[0] == 0 ? 0 : 1;
  EXPECT_EQ(edgeCut(g, layer), 100);
}

TEST(PartitionMetis, UniformWeightsAreBalanced) {
  const BlockForest f(kUnit, {4, 4, 4});
  const std::vector<double> w(f.numBlocks(), 1.0);
  for (int ranks : {2, 3, 4, 5, 9, 16}) {
    const std::vector<int> map = partitionMetis(f, w, ranks);
    expectValidMap(map, f, ranks);
    const double imb = imbalance(map, w, ranks);
    // the best possible is ceil(64 / ranks) / (64 / ranks)
    const double best = std::ceil(64.0 / ranks) / (64.0 / ranks);
    RecordProperty("imbalance_" + std::to_string(ranks), std::to_string(imb));
    std::printf("uniform 4x4x4 on %d ranks: imbalance %.4f (best %.4f)\n", ranks, imb, best);
    if (ranks <= 4) {
      EXPECT_LE(imb, 1.1) << ranks << " ranks";
    }
  }
}

TEST(PartitionMetis, CornerLoadBeatsTheEqualCountSplit) {
  const BlockForest f(kUnit, {4, 4, 4});
  // all weight in the 2x2x2 corner, and a field decaying away from the corner
  std::vector<double> corner(f.numBlocks(), 0.0), decay(f.numBlocks(), 0.0);
  for (int b = 0; b < f.numBlocks(); ++b) {
    const Index3 c = f.blockCoords(b);
    if (c[0] < 2 && c[1] < 2 && c[2] < 2) corner[b] = 100.0;
    decay[b] = std::exp(-1.5 * (c[0] + c[1] + c[2]));
  }
  for (const auto* w : {&corner, &decay}) {
    for (int ranks : {2, 4, 8}) {
      const std::vector<int> metis = partitionMetis(f, *w, ranks);
      expectValidMap(metis, f, ranks);
      const double naive = imbalance(equalCountSplit(f.numBlocks(), ranks), *w, ranks);
      const double got = imbalance(metis, *w, ranks);
      EXPECT_LT(got, naive) << ranks << " ranks";
      if (w == &corner) {
        // 8 equal heavy blocks split evenly over 2, 4 or 8 ranks; the light blocks weigh
        // 1/10001 of a heavy one each
        EXPECT_LE(got, 1.1) << ranks << " ranks";
      }
    }
  }
}

TEST(PartitionMetis, DeterministicForTheSameInput) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(0.0, 10.0);
  const BlockForest f(kUnit, {6, 5, 4}, {true, false, false});
  std::vector<double> w(f.numBlocks());
  for (double& x : w) x = u(rng);
  for (int ranks : {3, 12}) {
    const std::vector<int> first = partitionMetis(f, w, ranks);
    const BlockForest again(kUnit, {6, 5, 4}, {true, false, false});
    EXPECT_EQ(partitionMetis(again, w, ranks), first);
    EXPECT_EQ(partitionMetis(f, w, ranks), first);
  }
}

TEST(PartitionMetis, EdgeCasesAndErrors) {
  const BlockForest f(kUnit, {2, 2, 3});
  const std::vector<double> w(12, 1.0);
  EXPECT_EQ(partitionMetis(f, w, 1), std::vector<int>(12, 0));
  std::vector<int> identity(12);
  std::iota(identity.begin(), identity.end(), 0);
  EXPECT_EQ(partitionMetis(f, w, 12), identity);
  try {
    partitionMetis(f, w, 13);
    ADD_FAILURE() << "13 ranks on 12 blocks must throw";
  } catch (const DomainError& e) {
    EXPECT_NE(std::string(e.what()).find("13 ranks but only 12 blocks"), std::string::npos);
  }
  EXPECT_THROW(partitionMetis(f, w, 0), DomainError);
  EXPECT_THROW(partitionMetis(f, std::vector<double>(11, 1.0), 2), DomainError);
  // nearly as many ranks as blocks and one dominant block: every rank still gets a block
  std::vector<double> spike(12, 0.0);
  spike[5] = 1000.0;
  for (int ranks = 2; ranks <= 12; ++ranks)
    expectValidMap(partitionMetis(f, spike, ranks), f, ranks);
}

TEST(PartitionMetis, CustomEdgeWeights) {
  const BlockForest f(kUnit, {4, 4, 1});
  const std::vector<double> w(16, 1.0);
  BlockGraph g = blockGraph(f);
  std::vector<int> ew = g.edge_weights;
  // make cuts across y expensive: the partition should cut across x (between columns)
  for (int u = 0; u < 16; ++u) {
    for (int k = g.offsets[u]; k < g.offsets[u + 1]; ++k) {
      const Index3 a = f.blockCoords(u), b = f.blockCoords(g.adjacency[k]);
      if (a[0] == b[0]) ew[k] = 1000;  // same column: a cut here would split a column
    }
  }
  const std::vector<int> map = partitionMetis(f, w, 2, ew);
  expectValidMap(map, f, 2);
  for (int u = 0; u < 16; ++u) {
    const Index3 c = f.blockCoords(u);
    EXPECT_EQ(map[u], map[f.blockIndex({c[0], 0, 0})]) << "column " << c[0] << " was split";
  }
  std::vector<int> asymmetric = g.edge_weights;
  asymmetric[0] += 1;
  EXPECT_THROW(partitionMetis(f, w, 2, asymmetric), DomainError);
  EXPECT_THROW(partitionMetis(f, w, 2, std::vector<int>(3, 1)), DomainError);
  std::vector<int> zero = g.edge_weights;
  std::fill(zero.begin(), zero.end(), 0);
  EXPECT_THROW(partitionMetis(f, w, 2, zero), DomainError);
}

TEST(SpaceFillingCurve, MortonKeysInterleaveBits) {
  EXPECT_EQ(mortonKey({1, 0, 0}, 2), 1u);
  EXPECT_EQ(mortonKey({0, 1, 0}, 2), 2u);
  EXPECT_EQ(mortonKey({0, 0, 1}, 2), 4u);
  EXPECT_EQ(mortonKey({2, 0, 0}, 2), 8u);
  EXPECT_EQ(mortonKey({3, 3, 3}, 2), 63u);
  EXPECT_THROW(mortonKey({0, 0, 0}, 22), DomainError);
}

TEST(SpaceFillingCurve, HilbertVisitsEveryCellThroughFaceNeighbours) {
  for (int bits = 1; bits <= 4; ++bits) {
    const int n = 1 << bits;
    std::vector<Index3> cell_at(static_cast<std::size_t>(n) * n * n, Index3{-1, -1, -1});
    for (int z = 0; z < n; ++z) {
      for (int y = 0; y < n; ++y) {
        for (int x = 0; x < n; ++x) {
          const std::uint64_t key = hilbertKey({x, y, z}, bits);
          ASSERT_LT(key, cell_at.size());
          ASSERT_EQ(cell_at[key][0], -1) << "key " << key << " used twice";
          cell_at[key] = {x, y, z};
        }
      }
    }
    EXPECT_EQ(cell_at[0], (Index3{0, 0, 0}));
    for (std::size_t k = 1; k < cell_at.size(); ++k) {
      int steps = 0;
      for (int a = 0; a < 3; ++a) steps += std::abs(cell_at[k][a] - cell_at[k - 1][a]);
      ASSERT_EQ(steps, 1) << "bits " << bits << ", keys " << k - 1 << " -> " << k;
    }
  }
}

TEST(PartitionSfc, ContiguousAlongTheCurveAndBalanced) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const BlockForest f(kUnit, {5, 4, 3});
  std::vector<double> random(f.numBlocks()), corner(f.numBlocks(), 0.0);
  for (double& x : random) x = u(rng);
  corner[0] = corner[1] = corner[5] = 50.0;
  for (Curve curve : {Curve::kHilbert, Curve::kMorton}) {
    const std::vector<int> order = sfcOrder(f, curve);
    for (const auto* w : {&random, &corner}) {
      for (int ranks : {1, 2, 3, 7, 60}) {
        const std::vector<int> map = partitionSfc(f, *w, ranks, curve);
        expectValidMap(map, f, ranks);
        // rank numbers never decrease along the curve: each rank holds one contiguous chunk
        for (std::size_t k = 1; k < order.size(); ++k) {
          EXPECT_LE(map[order[k - 1]], map[order[k]]);
        }
        // every chunk weighs at most total/ranks + the heaviest block (capped vertex weights)
        const std::vector<int> vw = capHeavyBlocks(vertexWeights(f, *w), ranks);
        std::vector<long> load(ranks, 0);
        for (int b = 0; b < f.numBlocks(); ++b) load[map[b]] += vw[b];
        const long total = std::accumulate(vw.begin(), vw.end(), 0L);
        const long heaviest = *std::max_element(vw.begin(), vw.end());
        for (int r = 0; r < ranks; ++r) {
          EXPECT_LE(load[r] * ranks, total + heaviest * ranks) << "rank " << r;
        }
      }
    }
  }
  const std::vector<double> uniform(f.numBlocks(), 1.0);
  EXPECT_LE(imbalance(partitionSfc(f, uniform, 4), uniform, 4), 1.0 + 1e-12);  // 60 = 4 x 15
  EXPECT_THROW(partitionSfc(f, uniform, 61), DomainError);
}

TEST(PartitionSfc, EachCutIsTheNearestPrefixToItsTarget) {
  std::mt19937_64 rng(23);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const BlockForest f(kUnit, {5, 4, 3});
  std::vector<double> w(f.numBlocks());
  for (double& x : w) x = u(rng);
  const std::vector<int> order = sfcOrder(f, Curve::kHilbert);
  for (int ranks : {2, 3, 7}) {
    const std::vector<int> vw = capHeavyBlocks(vertexWeights(f, w), ranks);
    std::vector<long> prefix(order.size() + 1, 0);
    for (std::size_t k = 0; k < order.size(); ++k) prefix[k + 1] = prefix[k] + vw[order[k]];
    const long total = prefix.back();
    const std::vector<int> map = partitionSfc(f, w, ranks);
    for (int r = 1; r < ranks; ++r) {
      // brute force: the position whose prefix is nearest to r/ranks of the total, lower on ties
      std::size_t nearest = 0;
      for (std::size_t k = 1; k < prefix.size(); ++k) {
        if (std::labs(prefix[k] * ranks - r * total) <
            std::labs(prefix[nearest] * ranks - r * total)) {
          nearest = k;
        }
      }
      EXPECT_EQ(map[order[nearest - 1]], r - 1);
      EXPECT_EQ(map[order[nearest]], r);
    }
  }
}

TEST(Imbalance, MaxOverMean) {
  EXPECT_DOUBLE_EQ(imbalance(std::vector<int>{0, 0, 1}, std::vector<double>{1, 2, 1}, 2), 1.5);
  EXPECT_DOUBLE_EQ(imbalance(std::vector<int>{0, 1, 1}, std::vector<double>{1, 2, 1}, 3), 2.25);
  EXPECT_DOUBLE_EQ(imbalance(std::vector<int>{0, 1}, std::vector<double>{0, 0}, 2), 1.0);
  EXPECT_THROW(imbalance(std::vector<int>{0, 2}, std::vector<double>{1, 1}, 2), DomainError);
}

TEST(RepairEmptyRanks, EveryRankGetsABlockWithoutRaisingTheMaximum) {
  const BlockForest f(kUnit, {4, 4, 1});
  std::vector<double> w(16);
  for (int b = 0; b < 16; ++b) w[b] = 1.0 + b;
  std::vector<int> map(16, 0);
  for (int b = 8; b < 16; ++b) map[b] = 1;  // ranks 2 and 3 empty
  const std::vector<int> vw = vertexWeights(f, w);
  auto max_load = [&](const std::vector<int>& m) {
    std::vector<long> load(4, 0);
    for (int b = 0; b < 16; ++b) load[m[b]] += vw[b];
    return *std::max_element(load.begin(), load.end());
  };
  const long before = max_load(map);
  const std::vector<int> original = map;
  EXPECT_EQ(repairEmptyRanks(f, map, w, 4), 2);
  expectValidMap(map, f, 4);
  EXPECT_LE(max_load(map), before);
  int changed = 0;
  for (int b = 0; b < 16; ++b) changed += map[b] != original[b];
  EXPECT_EQ(changed, 2);
  // a valid map is left alone
  std::vector<int> fine = map;
  EXPECT_EQ(repairEmptyRanks(f, fine, w, 4), 0);
  EXPECT_EQ(fine, map);
}

TEST(RepairEmptyRanks, DonorGivesTheBorderBlockNearestHalfItsLoad) {
  const BlockForest f(kUnit, {4, 4, 1});
  std::vector<double> w(16, 1.0);
  w[14] = 7.0;  // on rank 0's border with rank 1 (block 15)
  w[0] = 7.0;   // as heavy, but inside rank 0
  std::vector<int> map(16, 0);
  map[15] = 1;  // rank 2 empty; rank 0 is the donor
  // vertex weights 1430 and 10001: rank 0 carries 13 * 1430 + 2 * 10001 = 38592; of its border
  // blocks 10, 11 (1430) and 14 (10001), block 14 is nearest to half of that
  EXPECT_EQ(repairEmptyRanks(f, map, w, 3), 1);
  std::vector<int> expected(16, 0);
  expected[15] = 1;
  expected[14] = 2;
  EXPECT_EQ(map, expected);
}

TEST(RelabelToMatch, UndoesAPermutationOfPartNumbers) {
  const BlockForest f(kUnit, {4, 4, 4});
  std::vector<double> w(f.numBlocks());
  for (int b = 0; b < f.numBlocks(); ++b) w[b] = 1.0 + (b % 5);
  const int ranks = 6;
  const std::vector<int> map = partitionMetis(f, w, ranks);
  const std::vector<int> perm = {3, 5, 0, 1, 4, 2};
  std::vector<int> renamed(map.size());
  for (std::size_t b = 0; b < map.size(); ++b) renamed[b] = perm[map[b]];
  EXPECT_EQ(relabelToMatch(f, renamed, map, w, ranks), map);
  // against an unrelated previous map the partition is kept, only names change
  const std::vector<int> previous = equalCountSplit(f.numBlocks(), ranks);
  const std::vector<int> matched = relabelToMatch(f, map, previous, w, ranks);
  EXPECT_DOUBLE_EQ(imbalance(matched, w, ranks), imbalance(map, w, ranks));
  for (int a = 0; a < f.numBlocks(); ++a) {
    for (int b = 0; b < f.numBlocks(); ++b) {
      ASSERT_EQ(map[a] == map[b], matched[a] == matched[b]);
    }
  }
}

}  // namespace
}  // namespace polydem::domain
