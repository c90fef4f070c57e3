// The hashed cell list on its own: its rounding guarantees, probed a few ulps around the cell
// borders where they matter.
#include "polydem/broadphase/cell_grid.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>

#include "broadphase/scenes.h"
#include "polydem/broadphase/overlap.h"

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
      grid.build(s.view(), all, 2 * r, boundsOf(s), false);
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
      grid.build(probe.view(), members, 2 * r, boundsOf(probe), false);
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
          grid.keysAround(Vec3(q, 0, 0), Vec3(q, 0, 0), small + grid.maxRadius(), lo, hi);
          EXPECT_TRUE(lo.x <= key.x && key.x <= hi.x) << "query box misses " << p.x();
        }
      }
    }
  }
}

// Checks that the grid holds exactly `members`, each in the cell of its centre, cells in
// strictly increasing (z, y, x) order, members of a cell in input order (the sort is stable),
// and, with a lookup table, that find() gives every cell.
void expectSortedByCell(const CellGrid& grid, const testing::Scene& s,
                        std::vector<std::int32_t> members, bool lookup) {
  std::vector<std::int32_t> seen;
  const auto cells = grid.cells();
  for (std::size_t c = 0; c < cells.size(); ++c) {
    const auto& cell = cells[c];
    EXPECT_LT(cell.begin, cell.end);
    if (c > 0) {
      EXPECT_TRUE(detail::cellBefore(cells[c - 1].key, cell.key));
      EXPECT_EQ(cells[c - 1].end, cell.begin);
    }
    if (lookup) {
      EXPECT_EQ(grid.find(cell.key), static_cast<std::int32_t>(c));
    }
    for (std::int32_t k = cell.begin; k < cell.end; ++k) {
      const detail::Meta& meta = grid.meta()[k];
      const Vec3& centre = s.centers[meta.index];
      EXPECT_EQ(grid.keyOf(centre.x(), centre.y(), centre.z()), cell.key);
      EXPECT_EQ(grid.coords().x[k], centre.x());
      EXPECT_EQ(grid.coords().r[k], s.radii[meta.index]);
      EXPECT_EQ(meta.uid, s.uids[meta.index]);
      EXPECT_EQ(meta.active, s.active[meta.index]);
      if (k > cell.begin) {
        EXPECT_LT(grid.meta()[k - 1].index, meta.index);
      }
      seen.push_back(meta.index);
    }
  }
  std::sort(seen.begin(), seen.end());
  std::sort(members.begin(), members.end());
  EXPECT_EQ(seen, members);
}

TEST(CellGrid, MembersAreSortedByCell) {
  for (const double offset : {0.0, 1e6}) {
    const testing::Scene s = testing::randomScene({.n = 3000,
                                                   .size_ratio = 5.0,
                                                   .inactive_fraction = 0.3,
                                                   .offset = Vec3::Constant(offset),
                                                   .seed = 4});
    std::vector<std::int32_t> even;
    for (std::int32_t i = 0; i < 3000; i += 2) even.push_back(i);
    // Small cells in a large box: hashed look-up; cells of the spheres' size: an array.
    for (const double reach : {1.0, 20.0}) {
      CellGrid grid;
      grid.build(s.view(), even, reach, boundsOf(s), true);
      EXPECT_EQ(grid.denseLookup(), reach > 1.0);
      expectSortedByCell(grid, s, even, true);
      EXPECT_EQ(grid.find({-5, -5, -5}), -1);
      EXPECT_EQ(grid.find({1000000, 0, 0}), -1);
      EXPECT_EQ(grid.find({0, 1000000, -1}), -1);
    }
  }
}

// Two clusters 1e4 cells apart: the lookup is a hash table, not an array over the empty box.
TEST(CellGrid, ClustersFarApart) {
  testing::Scene s = testing::randomScene({.n = 500, .solid_fraction = 0.3, .seed = 6});
  testing::Scene far = testing::randomScene(
      {.n = 500, .solid_fraction = 0.3, .offset = Vec3::Constant(2e4), .seed = 7});
  for (std::size_t i = 0; i < far.centers.size(); ++i) s.add(far.centers[i], far.radii[i]);
  s.finish(8);
  std::vector<std::int32_t> all(s.centers.size());
  for (std::size_t i = 0; i < all.size(); ++i) all[i] = static_cast<std::int32_t>(i);
  CellGrid grid;
  grid.build(s.view(), all, 2.0, boundsOf(s), true);
  EXPECT_FALSE(grid.denseLookup());
  expectSortedByCell(grid, s, all, true);
  EXPECT_EQ(grid.find({5000, 5000, 5000}), -1);
}

// The grid and a fresh one built for the same scene hold the same cells, members and coordinates.
void expectSameGrid(const CellGrid& reused, const CellGrid& fresh, const std::string& what) {
  ASSERT_EQ(reused.cells().size(), fresh.cells().size()) << what;
  for (std::size_t c = 0; c < fresh.cells().size(); ++c) {
    EXPECT_EQ(reused.cells()[c].key, fresh.cells()[c].key) << what;
    EXPECT_EQ(reused.cells()[c].begin, fresh.cells()[c].begin) << what;
    EXPECT_EQ(reused.cells()[c].end, fresh.cells()[c].end) << what;
  }
  ASSERT_EQ(reused.size(), fresh.size()) << what;
  for (std::size_t k = 0; k < fresh.size(); ++k) {
    EXPECT_EQ(reused.meta()[k].index, fresh.meta()[k].index) << what;
    EXPECT_EQ(reused.meta()[k].uid, fresh.meta()[k].uid) << what;
    EXPECT_EQ(reused.coords().x[k], fresh.coords().x[k]) << what;
    EXPECT_EQ(reused.coords().r[k], fresh.coords().r[k]) << what;
  }
}

// Rebuilt for the same members after they moved, a grid starts its sort from their last order;
// whether few of them changed cells (insertion sort), many did (it gives up for the radix sort)
// or the members changed (radix sort), it ends in the order a fresh grid has.
TEST(CellGrid, RebuildAfterMovesMatchesAFreshGrid) {
  testing::Scene s = testing::randomScene(
      {.n = 4000, .size_ratio = 3.0, .solid_fraction = 0.3, .inactive_fraction = 0.2, .seed = 12});
  // Cells of about 10 (the scene is about 80 across): a few members per cell, so that where a
  // member lands within its new cell matters.
  constexpr double kReach = 10.0;
  std::vector<std::int32_t> members;
  for (std::int32_t i = 0; i < 4000; i += 3) members.push_back(i);
  std::mt19937_64 rng(13);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  CellGrid reused;
  reused.build(s.view(), members, kReach, boundsOf(s), true);
  // Steps of 2 % of a cell (a few members cross a face), then 50 % (many do), then every centre
  // swapped with a random other (nothing of the last order is left).
  for (const double step : {0.2, 0.2, 5.0, -1.0}) {
    if (step > 0) {
      for (Vec3& c : s.centers) c += step * Vec3(unit(rng), unit(rng), unit(rng));
    } else {
      std::shuffle(s.centers.begin(), s.centers.end(), rng);
    }
    reused.build(s.view(), members, kReach, boundsOf(s), true);
    CellGrid fresh;
    fresh.build(s.view(), members, kReach, boundsOf(s), true);
    expectSameGrid(reused, fresh, "step " + std::to_string(step));
    expectSortedByCell(reused, s, members, true);
  }
  // Other members: the last order does not apply.
  members.pop_back();
  reused.build(s.view(), members, kReach, boundsOf(s), true);
  CellGrid fresh;
  fresh.build(s.view(), members, kReach, boundsOf(s), true);
  expectSameGrid(reused, fresh, "one member fewer");
}

// A scene spanning more than 2^62 cells is sorted by comparing keys instead of packing them.
TEST(CellGrid, HugeSparseExtent) {
  testing::Scene s;
  std::vector<std::int32_t> members;
  for (int i = 0; i < 200; ++i) {
    s.add(Vec3(1e-9 * (i % 7), 1e-9 * (i % 5), 1e-9 * (i % 3)) + Vec3::Constant(i < 100 ? 0 : 1e9),
          1e-9);
    members.push_back(i);
  }
  s.finish(3);
  CellGrid grid;
  grid.build(s.view(), members, 2e-9, boundsOf(s), true);
  EXPECT_LT(grid.edge(), 1e-3);  // cells stay small: no dense array over the extent
  expectSortedByCell(grid, s, members, true);
}

}  // namespace
}  // namespace polydem::broadphase
