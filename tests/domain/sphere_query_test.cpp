// blocksIntersectingSphere and ranksIntersectingSphere against brute force over all blocks and
// periodic images.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <set>
#include <tuple>
#include <vector>

#include "polydem/domain/block_forest.h"
#include "polydem/domain/domain_error.h"

namespace polydem::domain {
namespace {

// Every geometric test runs at three length scales: the answers must not depend on units.
const double kScales[] = {1e-3, 1.0, 1e3};

Aabb scaledBox(double scale, const Vec3& lo, const Vec3& hi) {
  return Aabb(scale * lo, scale * hi);
}

using HitKey = std::tuple<int, Index3>;

// Every (block, image) with blockBox(b).distance(c + shift) <= r, images up to +-3 per periodic
// axis: enough for centres at most half a domain length L outside and radii up to 1.5 L, since
// the image c + kL must come within r of [lo, hi] = [lo, lo + L].
std::vector<BlockHit> bruteSphere(const BlockForest& f, const Vec3& c, double r) {
  std::vector<BlockHit> out;
  const Vec3 length = f.domain().hi - f.domain().lo;
  Index3 lo{0, 0, 0}, hi{0, 0, 0};
  for (int a = 0; a < 3; ++a) {
    if (f.periodic(a)) lo[a] = -3, hi[a] = 3;
  }
  for (int b = 0; b < f.numBlocks(); ++b) {
    Index3 k;
    for (k[0] = lo[0]; k[0] <= hi[0]; ++k[0]) {
      for (k[1] = lo[1]; k[1] <= hi[1]; ++k[1]) {
        for (k[2] = lo[2]; k[2] <= hi[2]; ++k[2]) {
          const Vec3 shift(k[0] * length[0], k[1] * length[1], k[2] * length[2]);
          if (f.blockBox(b).distance(c + shift) <= r) out.push_back({b, k, shift});
        }
      }
    }
  }
  return out;
}

TEST(BlockForest, BlocksIntersectingSphereMatchesBruteForce) {
  std::mt19937_64 rng(2024);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const Periodic flags[] = {{false, false, false}, {true, false, true}, {true, true, true}};
  const Index3 shapes[] = {{4, 3, 5}, {1, 2, 3}, {2, 1, 1}};
  int images_seen = 0;
  for (double s : kScales) {
    for (const Periodic& p : flags) {
      for (const Index3& n : shapes) {
        const BlockForest f(scaledBox(s, Vec3(-1, 0.5, 2), Vec3(1, 2, 3)), n, p);
        const Vec3 length = f.domain().extent();
        for (int trial = 0; trial < 100; ++trial) {
          // centres up to half a domain length outside, radii up to 1.5 domain lengths
          const Vec3 c = f.domain().lo + length.cwiseProduct(Vec3(
                                             2 * u(rng) - 0.5, 2 * u(rng) - 0.5, 2 * u(rng) - 0.5));
          const double r =
              (trial % 3 == 0 ? 1.5 * length.minCoeff() : 0.6 * f.blockSize().minCoeff()) * u(rng);
          const std::vector<BlockHit> hits = f.blocksIntersectingSphere(c, r);
          const std::vector<BlockHit> brute = bruteSphere(f, c, r);
          std::set<HitKey> got, want;
          for (const BlockHit& h : hits) {
            EXPECT_TRUE(got.insert({h.block, h.image}).second) << "duplicate hit";
            EXPECT_EQ(h.shift,
                      Vec3(h.image[0] * length[0], h.image[1] * length[1], h.image[2] * length[2]));
            images_seen += h.image != Index3{0, 0, 0};
          }
          for (const BlockHit& h : brute) want.insert({h.block, h.image});
          ASSERT_EQ(got, want) << "scale " << s << " trial " << trial;
          EXPECT_TRUE(
              std::is_sorted(hits.begin(), hits.end(), [](const BlockHit& a, const BlockHit& b) {
                return std::tie(a.block, a.image) < std::tie(b.block, b.image);
              }));
          // the block holding the centre is hit with a zero shift
          const int home = f.blockOf(c);
          if (home >= 0 && f.blockBox(home).contains(c)) {
            EXPECT_TRUE(got.count({home, Index3{0, 0, 0}}));
          }
        }
      }
    }
  }
  EXPECT_GT(images_seen, 0);  // the periodic cases did exercise images
  const BlockForest f(Aabb(Vec3::Zero(), Vec3::Ones()), {2, 2, 2});
  EXPECT_TRUE(f.blocksIntersectingSphere(Vec3::Constant(0.5), -1.0).empty());
  EXPECT_THROW(f.blocksIntersectingSphere(Vec3(std::nan(""), 0, 0), 1.0), DomainError);
}

TEST(BlockForest, SpheresTouchingAFaceHitTheBlockBehindIt) {
  // The sphere reaches a block face at exactly distance r (closed test): that block is a hit.
  std::mt19937_64 rng(17);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (double s : kScales) {
    const BlockForest f(scaledBox(s, Vec3(-1.3, 0.2, 5), Vec3(2.1, 1.7, 6.1)), {7, 5, 3},
                        {false, true, false});
    for (int trial = 0; trial < 300; ++trial) {
      const int a = trial % 3;
      const auto edges = f.blockEdges(a);
      const int k = static_cast<int>(u(rng) * (f.counts()[a] + 1)) % (f.counts()[a] + 1);
      Vec3 c = f.domain().lo + f.domain().extent().cwiseProduct(Vec3(u(rng), u(rng), u(rng)));
      const double gap = f.blockSize()[a] * (0.05 + 1.5 * u(rng));
      c[a] = edges[k] + (trial % 2 ? gap : -gap);
      const double r = std::abs(c[a] - edges[k]);  // exact: the face is at distance r
      std::set<HitKey> got, want;
      for (const BlockHit& h : f.blocksIntersectingSphere(c, r)) got.insert({h.block, h.image});
      for (const BlockHit& h : bruteSphere(f, c, r)) want.insert({h.block, h.image});
      ASSERT_EQ(got, want) << "scale " << s << " trial " << trial;
    }
  }
}

TEST(BlockForest, RanksIntersectingSphereMatchesBruteForce) {
  std::mt19937_64 rng(99);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (double s : kScales) {
    BlockForest f(scaledBox(s, Vec3(0, 0, 0), Vec3(4, 4, 2)), {4, 4, 2}, {true, false, false});
    std::vector<int> map(f.numBlocks());
    for (int b = 0; b < f.numBlocks(); ++b) map[b] = (b * 7) % 5;
    f.setRankMap(map, 5);
    std::vector<RankHit> hits;
    for (int trial = 0; trial < 300; ++trial) {
      const Vec3 c = s * Vec3(6 * u(rng) - 1, 5 * u(rng) - 0.5, 3 * u(rng) - 0.5);
      const double r = s * 2.5 * u(rng);
      f.ranksIntersectingSphere(c, r, hits);
      std::set<std::tuple<int, Index3>> want;
      for (const BlockHit& h : bruteSphere(f, c, r)) want.insert({map[h.block], h.image});
      const std::vector<std::tuple<int, Index3>> want_sorted(want.begin(), want.end());
      std::vector<std::tuple<int, Index3>> got;
      for (const RankHit& h : hits) got.emplace_back(h.rank, h.image);
      EXPECT_EQ(got, want_sorted);  // unique and sorted by (rank, image)
    }
  }
}

// The exchange's shortcut: where sphereWithinRank says yes, the brute-force answer is the rank
// alone, unshifted (spheres touching block faces exactly included); it says yes often enough to
// matter, and never with a periodic axis.
TEST(BlockForest, SphereWithinRankOnlyWhenTheQueryFindsTheRankAlone) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (double s : kScales) {
    BlockForest f(scaledBox(s, Vec3(0, 0, 0), Vec3(8, 6, 2)), {8, 6, 2});
    std::vector<int> map(f.numBlocks());
    for (int b = 0; b < f.numBlocks(); ++b) map[b] = f.blockCoords(b)[0] / 3;  // slabs of 3
    f.setRankMap(map, 3);
    int yes = 0;
    for (int trial = 0; trial < 600; ++trial) {
      Vec3 c = s * Vec3(8 * u(rng), 6 * u(rng), 2 * u(rng));
      double r = s * 1.5 * u(rng);
      if (trial % 3 == 0) {  // exactly touching a block face along x
        const auto edges = f.blockEdges(0);
        const int k = 1 + trial % (f.counts()[0] - 1);
        r = std::abs(c.x() - edges[k]);
      }
      const int rank = f.ownerOf(c);
      if (!f.sphereWithinRank(c, r, rank)) continue;
      ++yes;
      for (const BlockHit& h : bruteSphere(f, c, r)) {
        EXPECT_EQ(map[h.block], rank) << "scale " << s << " trial " << trial;
        EXPECT_EQ(h.image, (Index3{0, 0, 0}));
      }
    }
    EXPECT_GT(yes, 50) << "scale " << s;
  }
  BlockForest periodic(Aabb(Vec3(0, 0, 0), Vec3(8, 6, 2)), {8, 6, 2}, {false, false, true});
  EXPECT_FALSE(periodic.sphereWithinRank(Vec3(4, 3, 1), 0.01, 0));
  EXPECT_FALSE(periodic.sphereWithinRank(Vec3(4, NAN, 1), 0.01, 0));
}

}  // namespace
}  // namespace polydem::domain
