// fitBlockCounts: enough occupied blocks per rank wherever the particles are in the domain,
// scale-free, limited by the minimum edge and the block budget.
#include "polydem/domain/block_fit.h"

#include <gtest/gtest.h>

#include <vector>

#include "polydem/domain/domain_error.h"

namespace polydem::domain {
namespace {

/// Centroids of an nx x ny x nz lattice of pitch `pitch` starting at `origin`.
std::vector<Vec3> lattice(const Vec3& origin, int nx, int ny, int nz, double pitch) {
  std::vector<Vec3> out;
  for (int k = 0; k < nz; ++k) {
    for (int j = 0; j < ny; ++j) {
      for (int i = 0; i < nx; ++i) out.push_back(origin + pitch * Vec3(i + 0.5, j + 0.5, k + 0.5));
    }
  }
  return out;
}

Aabb boundsOf(const std::vector<Vec3>& points, double radius) {
  Vec3 lo = points[0], hi = points[0];
  for (const Vec3& x : points) {
    lo = lo.cwiseMin(x);
    hi = hi.cwiseMax(x);
  }
  return Aabb(lo, hi).inflated(radius);
}

struct Fit {
  Index3 counts;
  std::int64_t occupied;
};

Fit fit(const Aabb& domain, const std::vector<Vec3>& points, double radius, int ranks,
        double min_edge = 0.0) {
  BlockFitOptions o;
  o.ranks = ranks;
  o.min_block_edge = min_edge;
  const Index3 n = fitBlockCounts(domain, boundsOf(points, radius), o, [&](const Index3& c) {
    return countOccupiedBlocks(domain, c, {false, false, false}, points);
  });
  return {n, countOccupiedBlocks(domain, n, {false, false, false}, points)};
}

TEST(FitBlockCounts, APileOnAWideFloorGetsEnoughOccupiedBlocks) {
  // 20 x 20 x 10 unit cubes in the middle of a domain 4 times as wide and 5 times as high: blocks
  // cut from the domain alone (chooseBlockCounts) leave the pile in a few of them.
  const std::vector<Vec3> pile = lattice(Vec3(30, 30, 0), 20, 20, 10, 1.0);
  const Aabb domain(Vec3(0, 0, -20), Vec3(80, 80, 30));
  for (int ranks : {1, 2, 8, 16, 64}) {
    const Fit f = fit(domain, pile, 0.87, ranks);
    EXPECT_GE(f.occupied, 16 * ranks) << ranks << " ranks";
    // not needlessly fine: the previous (coarser) grid in the sequence had too few
    EXPECT_LT(f.occupied, 4 * 16 * ranks) << ranks << " ranks";
    // The domain-only rule, for contrast: a few occupied blocks per rank at most.
    const std::int64_t old_rule =
        countOccupiedBlocks(domain, chooseBlockCounts(domain, ranks, 8), {}, pile);
    if (ranks > 1) {
      EXPECT_LE(old_rule, 4 * ranks) << ranks << " ranks";
    }
  }
}

TEST(FitBlockCounts, ScaleFreeAndNearlyCubic) {
  const std::vector<Vec3> unit = lattice(Vec3(1, 2, 0), 30, 10, 6, 1.0);
  const Aabb unit_domain(Vec3(0, 0, -1), Vec3(40, 15, 10));
  for (int ranks : {2, 7, 16}) {
    const Fit reference = fit(unit_domain, unit, 0.87, ranks);
    for (double s : {1e-3, 1e3}) {
      std::vector<Vec3> scaled;
      for (const Vec3& x : unit) scaled.push_back(s * x);
      const Aabb d(s * unit_domain.lo, s * unit_domain.hi);
      EXPECT_EQ(fit(d, scaled, 0.87 * s, ranks).counts, reference.counts) << "scale " << s;
    }
    const Vec3 edge = unit_domain.extent().cwiseQuotient(
        Vec3(reference.counts[0], reference.counts[1], reference.counts[2]));
    EXPECT_LT(edge.maxCoeff() / edge.minCoeff(), 1.5) << ranks << " ranks";
  }
}

TEST(FitBlockCounts, AFlatLayerGetsColumns) {
  // One layer of particles: the first edge comes from its area, so the blocks are not slivers.
  const std::vector<Vec3> layer = lattice(Vec3(0, 0, 0), 64, 64, 1, 1.0);
  const Aabb domain(Vec3(0, 0, -5), Vec3(64, 64, 5));
  const Fit f = fit(domain, layer, 0.6, 16);
  EXPECT_GE(f.occupied, 256);
  EXPECT_LE(f.counts[2], 3);
}

TEST(FitBlockCounts, MinimumEdgeAndTooFewParticles) {
  // 10 particles cannot fill 16 blocks per rank on 4 ranks: the grid stops at the minimum edge,
  // and still has a block per rank.
  const std::vector<Vec3> few = lattice(Vec3(0, 0, 0), 10, 1, 1, 1.0);
  const Aabb domain(Vec3(-1, -1, -1), Vec3(11, 2, 2));
  const Fit f = fit(domain, few, 0.5, 4, 1.0);
  for (int a = 0; a < 3; ++a) EXPECT_GE(domain.extent()[a] / f.counts[a], 1.0);
  EXPECT_GE(std::int64_t{f.counts[0]} * f.counts[1] * f.counts[2], 4);
  EXPECT_LE(f.occupied, 10);
  // Without a minimum edge, the particle count stops the refinement: one occupied block per 4
  // particles (at least one per rank) is enough, instead of blocks refined to the budget.
  BlockFitOptions o;
  o.ranks = 4;
  o.particles = static_cast<std::int64_t>(few.size());
  const Index3 n = fitBlockCounts(domain, boundsOf(few, 0.5), o, [&](const Index3& c) {
    return countOccupiedBlocks(domain, c, {}, few);
  });
  EXPECT_GE(countOccupiedBlocks(domain, n, {}, few), 4);
  EXPECT_LT(std::int64_t{n[0]} * n[1] * n[2], 1000);
}

TEST(FitBlockCounts, BlockBudgetAndBadOptions) {
  // A speck in a huge domain: the budget, not the occupancy, decides.
  const std::vector<Vec3> speck = lattice(Vec3(0, 0, 0), 2, 2, 2, 1.0);
  const Aabb domain(Vec3(-1e4, -1e4, -1e4), Vec3(1e4, 1e4, 1e4));
  BlockFitOptions o;
  o.ranks = 4;
  o.max_blocks = 100000;
  const Index3 n = fitBlockCounts(domain, boundsOf(speck, 0.5), o, [&](const Index3& c) {
    return countOccupiedBlocks(domain, c, {}, speck);
  });
  EXPECT_LE(std::int64_t{n[0]} * n[1] * n[2], o.max_blocks);
  EXPECT_GE(std::int64_t{n[0]} * n[1] * n[2], o.ranks);
  o.occupied_per_rank = 0;
  EXPECT_THROW(fitBlockCounts(domain, domain, o, [](const Index3&) { return 0; }), DomainError);
}

}  // namespace
}  // namespace polydem::domain
