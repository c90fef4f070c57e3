#include "polydem/domain/block_forest.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "polydem/core/strings.h"
#include "polydem/domain/domain_error.h"

namespace polydem::domain {
namespace {

// Every geometric test runs at three length scales: the answers must not depend on units.
const double kScales[] = {1e-3, 1.0, 1e3};

Aabb scaledBox(double scale, const Vec3& lo, const Vec3& hi) {
  return Aabb(scale * lo, scale * hi);
}

TEST(Aabb, ContainsIntersectsDistanceInflatedVolume) {
  for (double s : kScales) {
    const Aabb box = scaledBox(s, Vec3(-1, 0, 2), Vec3(1, 3, 6));
    EXPECT_DOUBLE_EQ(box.volume(), 2 * 3 * 4 * s * s * s);
    EXPECT_TRUE(box.contains(s * Vec3(0, 1, 3)));
    EXPECT_TRUE(box.contains(s * Vec3(1, 3, 6)));  // closed: corners count
    EXPECT_FALSE(box.contains(s * Vec3(1.5, 1, 3)));
    EXPECT_EQ(box.distance(s * Vec3(0, 1, 3)), 0.0);
    EXPECT_DOUBLE_EQ(box.distance(s * Vec3(4, 1, 3)), 3 * s);                  // face
    EXPECT_DOUBLE_EQ(box.distance(s * Vec3(4, 7, 3)), 5 * s);                  // edge: 3-4-5
    EXPECT_DOUBLE_EQ(box.distance(s * Vec3(-3, -2, 0)), std::sqrt(12.0) * s);  // corner
    EXPECT_TRUE(box.intersects(scaledBox(s, Vec3(1, 3, 6), Vec3(2, 4, 7))));   // touching corner
    EXPECT_FALSE(box.intersects(scaledBox(s, Vec3(1.1, 0, 2), Vec3(2, 3, 6))));
    const Aabb big = box.inflated(0.5 * s);
    EXPECT_DOUBLE_EQ(big.volume(), 3 * 4 * 5 * s * s * s);
    EXPECT_DOUBLE_EQ(big.distance(s * Vec3(4, 1, 3)), 2.5 * s);
    EXPECT_TRUE(box.inflated(-2 * s).empty());
    EXPECT_EQ(box.inflated(-2 * s).volume(), 0.0);
  }
}

TEST(BlockForest, IndexRoundTripAndBoxesTileTheDomain) {
  for (double s : kScales) {
    const BlockForest f(scaledBox(s, Vec3(-2, 1, 0.5), Vec3(3, 4, 2)), {5, 3, 4});
    ASSERT_EQ(f.numBlocks(), 60);
    double volume = 0;
    for (int b = 0; b < f.numBlocks(); ++b) {
      const Index3 c = f.blockCoords(b);
      EXPECT_EQ(f.blockIndex(c), b);
      EXPECT_EQ(b, c[0] + 5 * (c[1] + 3 * c[2]));
      volume += f.blockBox(b).volume();
      // the +x neighbour shares the face exactly
      if (c[0] + 1 < 5) {
        const int nb = f.blockIndex({c[0] + 1, c[1], c[2]});
        EXPECT_EQ(f.blockBox(b).hi.x(), f.blockBox(nb).lo.x());
      }
    }
    EXPECT_NEAR(volume, f.domain().volume(), 1e-12 * f.domain().volume());
    EXPECT_EQ(f.blockIndex({5, 0, 0}), -1);
    EXPECT_EQ(f.blockIndex({0, -1, 0}), -1);
    EXPECT_EQ(f.blockBox(0).lo, f.domain().lo);
    EXPECT_EQ(f.blockBox(59).hi, f.domain().hi);
  }
}

TEST(BlockForest, BlockOfInteriorFaceCornerAndOutsidePoints) {
  for (double s : kScales) {
    const BlockForest f(scaledBox(s, Vec3(-2, 1, 0.5), Vec3(3, 4, 2)), {5, 3, 4});
    for (int b = 0; b < f.numBlocks(); ++b) {
      const Aabb box = f.blockBox(b);
      const Index3 c = f.blockCoords(b);
      EXPECT_EQ(f.blockOf(box.center()), b);
      // The lower corner is shared by up to 8 blocks; the half-open rule gives it to this one.
      EXPECT_EQ(f.blockOf(box.lo), b);
      // A point on the upper x face belongs to the upper neighbour, or to b on the domain face.
      const Vec3 on_face(box.hi.x(), box.center().y(), box.center().z());
      EXPECT_EQ(f.blockOf(on_face), c[0] + 1 < 5 ? f.blockIndex({c[0] + 1, c[1], c[2]}) : b);
      // The upper corner belongs to the block diagonally above (clamped at the domain faces).
      const Index3 up{std::min(c[0] + 1, 4), std::min(c[1] + 1, 2), std::min(c[2] + 1, 3)};
      EXPECT_EQ(f.blockOf(box.hi), f.blockIndex(up));
    }
    const Aabb d = f.domain();
    EXPECT_EQ(f.blockOf(d.hi), f.numBlocks() - 1);  // non-periodic upper faces are inside
    EXPECT_EQ(f.blockOf(d.lo), 0);
    const double eps = 1e-9 * s;
    EXPECT_EQ(f.blockOf(Vec3(d.hi.x() + eps, d.center().y(), d.center().z())), -1);
    EXPECT_EQ(f.blockOf(Vec3(d.center().x(), d.lo.y() - eps, d.center().z())), -1);
    EXPECT_EQ(f.blockOf(Vec3(d.center().x(), d.center().y(), std::nan(""))), -1);
    EXPECT_EQ(f.ownerOf(Vec3(d.hi.x() + eps, d.center().y(), d.center().z())), -1);
  }
}

TEST(BlockForest, BlockOfFollowsTheHalfOpenRuleForRandomPoints) {
  std::mt19937_64 rng(7);
  for (double s : kScales) {
    const BlockForest f(scaledBox(s, Vec3(-0.3, 0.1, 7), Vec3(0.4, 0.9, 7.7)), {7, 3, 6});
    std::uniform_real_distribution<double> u(0.0, 1.0);
    for (int i = 0; i < 2000; ++i) {
      const Vec3 x = f.domain().lo + f.domain().extent().cwiseProduct(Vec3(u(rng), u(rng), u(rng)));
      const int b = f.blockOf(x);
      ASSERT_GE(b, 0);
      const Aabb box = f.blockBox(b);
      for (int a = 0; a < 3; ++a) {
        EXPECT_LE(box.lo[a], x[a]);
        EXPECT_TRUE(x[a] < box.hi[a] || box.hi[a] == f.domain().hi[a]);
      }
    }
  }
}

TEST(BlockForest, FacesBelongToTheUpperBlockExactly) {
  // Awkward domains and counts, so that (x - lo) / size rounds the wrong way for some faces: the
  // stored edges decide, not the division.
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int trial = 0; trial < 200; ++trial) {
    const double s = std::pow(10.0, 6 * u(rng) - 3);
    const Vec3 lo = s * Vec3(20 * u(rng) - 10, 20 * u(rng) - 10, 20 * u(rng) - 10);
    const Vec3 hi = lo + s * Vec3(0.1 + u(rng), 0.1 + u(rng), 0.1 + u(rng));
    const Index3 n{1 + static_cast<int>(13 * u(rng)), 1 + static_cast<int>(13 * u(rng)),
                   1 + static_cast<int>(13 * u(rng))};
    const BlockForest f(Aabb(lo, hi), n);
    const Vec3 mid = f.domain().center();
    for (int a = 0; a < 3; ++a) {
      const auto edges = f.blockEdges(a);
      for (int k = 0; k < n[a]; ++k) {
        Vec3 x = mid;
        x[a] = edges[k];
        ASSERT_EQ(f.blockCoords(f.blockOf(x))[a], k) << "face " << k << " of axis " << a;
        if (k > 0) {
          x[a] = std::nextafter(edges[k], -INFINITY);
          ASSERT_EQ(f.blockCoords(f.blockOf(x))[a], k - 1) << "just below face " << k;
        }
      }
      Vec3 top = mid;
      top[a] = edges[n[a]];
      EXPECT_EQ(f.blockCoords(f.blockOf(top))[a], n[a] - 1);
      top[a] = std::nextafter(edges[n[a]], INFINITY);
      EXPECT_EQ(f.blockOf(top), -1);
    }
  }
}

TEST(BlockForest, WrapAndBlockOfAlongPeriodicAxes) {
  for (double s : kScales) {
    const BlockForest f(scaledBox(s, Vec3(-1, 0, 0), Vec3(3, 2, 1)), {4, 2, 1},
                        {true, false, true});
    const Aabb d = f.domain();
    const double lx = d.extent().x();
    // x == hi is the same point as lo: block 0 along x
    EXPECT_EQ(f.blockOf(Vec3(d.hi.x(), 0.5 * s, 0.5 * s)), f.blockIndex({0, 0, 0}));
    EXPECT_EQ(f.wrap(Vec3(d.hi.x(), 0.5 * s, 0.5 * s)).x(), d.lo.x());
    // just below lo: last block along x
    EXPECT_EQ(f.blockOf(Vec3(d.lo.x() - 0.1 * s, 0.5 * s, 0.5 * s)), f.blockIndex({3, 0, 0}));
    // several domain lengths away
    const Vec3 far(d.lo.x() + 2.5 * s + 3 * lx, 1.5 * s, 0.25 * s - 5 * d.extent().z());
    const Vec3 w = f.wrap(far);
    EXPECT_NEAR(w.x(), d.lo.x() + 2.5 * s, 1e-12 * s);
    EXPECT_NEAR(w.z(), 0.25 * s, 1e-12 * s);
    EXPECT_EQ(w.y(), far.y());
    EXPECT_EQ(f.blockOf(far), f.blockIndex({2, 1, 0}));
    // points inside come back bit for bit
    const Vec3 inside(0.3 * s, 0.7 * s, 0.9 * s);
    EXPECT_EQ(f.wrap(inside), inside);
    // just below lo, by one ulp: the wrap must stay in [lo, hi) even where lo + L rounds to hi
    const Vec3 below(std::nextafter(d.lo.x(), -INFINITY), 0.5 * s, 0.5 * s);
    EXPECT_GE(f.wrap(below).x(), d.lo.x());
    EXPECT_LT(f.wrap(below).x(), d.hi.x());
    EXPECT_GE(f.blockOf(below), 0);
    // the non-periodic y axis still has an outside
    EXPECT_EQ(f.blockOf(Vec3(0, 2.5 * s, 0)), -1);
    EXPECT_EQ(f.blockOf(Vec3(0, d.hi.y(), 0)), f.blockIndex({1, 1, 0}));
  }
}

// Brute-force neighbour definition: every axis differs by at most one cell, counting the
// wrap-around on periodic axes, and the block is not the same block.
std::vector<int> bruteNeighbours(const BlockForest& f, int b) {
  std::vector<int> out;
  const Index3 cb = f.blockCoords(b);
  for (int o = 0; o < f.numBlocks(); ++o) {
    if (o == b) continue;
    const Index3 co = f.blockCoords(o);
    bool near = true;
    for (int a = 0; a < 3; ++a) {
      const int n = f.counts()[a];
      int diff = std::abs(cb[a] - co[a]);
      if (f.periodic(a)) diff = std::min(diff, n - diff);
      near = near && diff <= 1;
    }
    if (near) out.push_back(o);
  }
  return out;
}

TEST(BlockForest, NeighbourCounts) {
  const Aabb unit(Vec3::Zero(), Vec3::Ones());
  const BlockForest open(unit, {3, 3, 3});
  EXPECT_EQ(open.neighbours(open.blockIndex({1, 1, 1})).size(), 26u);
  EXPECT_EQ(open.neighbours(open.blockIndex({0, 0, 0})).size(), 7u);
  EXPECT_EQ(open.neighbours(open.blockIndex({2, 2, 2})).size(), 7u);
  EXPECT_EQ(open.neighbours(open.blockIndex({1, 0, 0})).size(), 11u);  // edge block
  EXPECT_EQ(open.neighbours(open.blockIndex({1, 1, 0})).size(), 17u);  // face block
  const BlockForest torus(unit, {3, 3, 3}, {true, true, true});
  for (int b = 0; b < torus.numBlocks(); ++b) EXPECT_EQ(torus.neighbours(b).size(), 26u);
  // 2 blocks along a periodic axis: the other block is the neighbour on both sides, once.
  const BlockForest two(unit, {2, 2, 2}, {true, true, true});
  for (int b = 0; b < two.numBlocks(); ++b) EXPECT_EQ(two.neighbours(b).size(), 7u);
  // 1 block along a periodic axis: that axis adds nothing (a block is not its own neighbour).
  const BlockForest one(unit, {1, 3, 3}, {true, false, false});
  EXPECT_EQ(one.neighbours(one.blockIndex({0, 1, 1})).size(), 8u);
  const BlockForest single(unit, {1, 1, 1}, {true, true, true});
  EXPECT_TRUE(single.neighbours(0).empty());
}

TEST(BlockForest, NeighboursMatchBruteForceAndAreSortedAndSymmetric) {
  const Aabb box(Vec3(0, 0, 0), Vec3(4, 2, 3));
  const Periodic flags[] = {{false, false, false}, {true, false, true}, {true, true, true}};
  const Index3 shapes[] = {{4, 2, 3}, {1, 5, 2}, {2, 1, 4}, {3, 3, 1}};
  for (const Periodic& p : flags) {
    for (const Index3& n : shapes) {
      const BlockForest f(box, n, p);
      for (int b = 0; b < f.numBlocks(); ++b) {
        const std::vector<int> nbs = f.neighbours(b);
        EXPECT_EQ(nbs, bruteNeighbours(f, b));  // brute force is ascending
        for (int o : nbs) {
          const std::vector<int> back = f.neighbours(o);
          EXPECT_TRUE(std::binary_search(back.begin(), back.end(), b));
        }
      }
    }
  }
}

TEST(BlockForest, RankMapQueries) {
  BlockForest f(Aabb(Vec3::Zero(), Vec3(3, 1, 1)), {3, 1, 1});
  EXPECT_EQ(f.numRanks(), 1);
  EXPECT_EQ(f.blocksOfRank(0).size(), 3u);
  f.setRankMap({2, 0, 2});
  EXPECT_EQ(f.numRanks(), 3);
  EXPECT_EQ(std::vector<int>(f.blocksOfRank(2).begin(), f.blocksOfRank(2).end()),
            (std::vector<int>{0, 2}));
  EXPECT_TRUE(f.blocksOfRank(1).empty());
  EXPECT_EQ(f.ownerOf(Vec3(0.5, 0.5, 0.5)), 2);
  EXPECT_EQ(f.ownerOf(Vec3(1.5, 0.5, 0.5)), 0);
  EXPECT_EQ(f.ownerOf(Vec3(1.0, 0.5, 0.5)), 0);  // face between blocks 0 and 1 -> block 1
  EXPECT_EQ(f.neighbourRanks(0), (std::vector<int>{2}));
  EXPECT_EQ(f.neighbourRanks(2), (std::vector<int>{0}));
  f.setRankMap({0, 1, 3}, 5);
  EXPECT_EQ(f.numRanks(), 5);
  EXPECT_TRUE(f.blocksOfRank(4).empty());
  EXPECT_THROW(f.setRankMap({0, 1}), DomainError);
  EXPECT_THROW(f.setRankMap({0, 1, 5}, 5), DomainError);
  EXPECT_THROW(f.setRankMap({0, -1, 2}), DomainError);
}

TEST(BlockForest, RejectsBadDomainsAndCounts) {
  const Aabb unit(Vec3::Zero(), Vec3::Ones());
  EXPECT_THROW(BlockForest(unit, {0, 1, 1}), DomainError);
  EXPECT_THROW(BlockForest(Aabb(Vec3::Zero(), Vec3(1, 0, 1)), {1, 1, 1}), DomainError);
  EXPECT_THROW(BlockForest(Aabb(Vec3::Zero(), Vec3(1, INFINITY, 1)), {1, 1, 1}), DomainError);
  EXPECT_THROW(BlockForest(unit, {2000, 2000, 2000}), DomainError);
  // blocks thinner than the resolution of the coordinates
  EXPECT_THROW(BlockForest(Aabb(Vec3(1e6, 0, 0), Vec3(1e6 + 1e-8, 1, 1)), {1000, 1, 1}),
               DomainError);
}

// The neighbour ranks of the step's exchange: every rank owning a block within the distance (by
// the exact box distance, across periodic faces too), and a symmetric relation, which the
// exchange needs (each rank waits for one message from each of its neighbours).
TEST(BlockForest, RanksWithinCoverTheDistanceAndAreSymmetric) {
  const Aabb box(Vec3(0, 0, 0), Vec3(4, 3, 2));
  for (const Periodic periodic : {Periodic{false, false, false}, Periodic{true, false, true}}) {
    BlockForest f(box, {8, 6, 3}, periodic);
    const int ranks = 7;
    std::vector<int> map(f.numBlocks());
    for (int b = 0; b < f.numBlocks(); ++b) map[b] = (b * 5 + b / 9) % ranks;
    f.setRankMap(map, ranks);
    for (const double d : {0.0, 0.3, 0.9}) {
      SCOPED_TRACE(cat("distance ", d, ", periodic x ", periodic[0]));
      std::vector<std::vector<int>> within(ranks);
      for (int r = 0; r < ranks; ++r) within[r] = f.ranksWithin(r, d);
      for (int r = 0; r < ranks; ++r) {
        for (int s : within[r]) {
          EXPECT_NE(s, r);
          EXPECT_TRUE(std::binary_search(within[s].begin(), within[s].end(), r)) << r << " " << s;
        }
      }
      // Exact: blocks b, c are within d if a sphere of radius d around some point of b reaches
      // c; sampling b's corners and centre with the sphere query gives a subset of that.
      for (int b = 0; b < f.numBlocks(); ++b) {
        const Aabb bb = f.blockBox(b);
        for (const Vec3& x : {bb.lo, bb.hi, bb.center(), Vec3(bb.lo.x(), bb.hi.y(), bb.lo.z())}) {
          for (const auto& hit : f.ranksIntersectingSphere(x, d)) {
            const int r = f.rankOfBlock(b);
            if (hit.rank == r) continue;
            EXPECT_TRUE(std::binary_search(within[r].begin(), within[r].end(), hit.rank))
                << "block " << b << " of rank " << r << " reaches rank " << hit.rank;
          }
        }
      }
    }
  }
}

}  // namespace
}  // namespace polydem::domain
