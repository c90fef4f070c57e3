// The hashed cell list on its own: its rounding guarantees, probed a few ulps around the cell
// borders where they matter.
#include "broadphase/cell_grid.h"

#include <gtest/gtest.h>

#include <cmath>

#include "broadphase/overlap.h"
#include "broadphase/scenes.h"

namespace polydem::broadphase {
namespace {

using detail::CellGrid;
using detail::CellKey;

double ulpsAway(double x, int ulps) {
  for (int k = 0; k < std::abs(ulps); ++k) x = std::nextafter(x, ulps * 1e300);
  return x;
}

detail::SceneBounds boundsOf(const testing::Scene& s) {
  detail::SceneBounds b{s.centers[0], s.centers[0], 0.0};
  for (std::size_t i = 0; i < s.centers.size(); ++i) {
    b.lo = b.lo.cwiseMin(s.centers[i]);
    b.hi = b.hi.cwiseMax(s.centers[i]);
    b.max_radius = std::max(b.max_radius, s.radii[i]);
  }
  return b;
}

// Two members within reach are never more than one cell apart; a query's box holds the cell of
// every member within its reach. Members sit a few ulps around the cell borders.
TEST(CellGrid, RoundingNeverSplitsAPairAcrossTwoCells) {
  for (const double lowest : {-2.3, 0.1, 3.7, 1e6 + 0.1}) {
    for (const double r : {0.05, 0.35, 1e-3}) {
      // Build once to learn the edge, then put members at its borders.
      testing::Scene s;
      s.add(Vec3(lowest, 0, 0), r);
      s.add(Vec3(lowest + 500 * 2 * r, 0, 0), r);
      s.finish(1);
      const std::vector<std::int32_t> all = {0, 1};
      CellGrid grid;
      grid.build(s.view(), all, 2 * r, boundsOf(s));
      const double edge = grid.edge();
      EXPECT_GE(edge, 2 * r);
      EXPECT_LE(edge, 2 * r * (1 + 1e-9));
      testing::Scene probe = s;
      for (int m = 1; m < 500; m += 3) {
        for (int ulps = -3; ulps <= 3; ++ulps) {
          probe.add(Vec3(ulpsAway(lowest + m * edge, ulps), 0, 0), r);
        }
      }
      probe.finish(2);
      std::vector<std::int32_t> members(probe.centers.size());
      for (std::size_t i = 0; i < members.size(); ++i) members[i] = static_cast<std::int32_t>(i);
      grid.build(probe.view(), members, 2 * r, boundsOf(probe));
      ASSERT_EQ(grid.edge(), edge);  // same extent, same edge
      const double small = 0.1 * r;
      for (std::size_t i = 2; i < probe.centers.size(); ++i) {
        const Vec3& p = probe.centers[i];
        const CellKey key = grid.keyOf(p.x(), p.y(), p.z());
        for (const double other : {p.x() + 2 * r, p.x() - 2 * r}) {
          if (!withinReach(p.x(), 0, 0, r, other, 0, 0, r, 0.0)) continue;
          const CellKey okey = grid.keyOf(other, 0, 0);
          EXPECT_LE(std::abs(okey.x - key.x), 1) << "pair split at " << p.x();
        }
        for (const double q : {p.x() + r + small, p.x() - r - small}) {
          if (!withinReach(p.x(), 0, 0, r, q, 0, 0, small, 0.0)) continue;
          CellKey lo, hi;
          grid.boxAround(q, 0, 0, small + grid.maxRadius(), lo, hi);
          EXPECT_TRUE(lo.x <= key.x && key.x <= hi.x) << "query box misses " << p.x();
        }
      }
    }
  }
}

TEST(CellGrid, MembersAreGroupedByCell) {
  const testing::Scene s = testing::randomScene({.n = 2000, .size_ratio = 5.0, .seed = 4});
  std::vector<std::int32_t> members;
  for (std::int32_t i = 0; i < 2000; i += 2) members.push_back(i);
  CellGrid grid;
  grid.build(s.view(), members, 1.0, boundsOf(s));
  std::size_t total = 0;
  for (std::size_t c = 0; c < grid.cells().size(); ++c) {
    const CellGrid::Cell& cell = grid.cells()[c];
    EXPECT_EQ(grid.find(cell.key), static_cast<std::int32_t>(c));
    for (std::int32_t k = cell.begin; k < cell.end; ++k) {
      const Vec3& centre = s.centers[grid.index()[k]];
      EXPECT_EQ(grid.keyOf(centre.x(), centre.y(), centre.z()), cell.key);
      EXPECT_EQ(grid.items()[k].r, s.radii[grid.index()[k]]);
      EXPECT_EQ(grid.index()[k] % 2, 0);
    }
    total += cell.end - cell.begin;
  }
  EXPECT_EQ(total, members.size());
  EXPECT_EQ(grid.find({-5, -5, -5}), -1);
}

}  // namespace
}  // namespace polydem::broadphase
