// CellOrder: the order of a grid's cells as a storage order. A set permuted by it is gathered
// front to back by a grid of the same reach, its cells follow in (z, y, x) order with ties by
// index, entries past `count` (ghosts) are not touched, and a warm call allocates nothing.
#include "polydem/broadphase/cell_order.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "common/allocation_counter.h"
#include "polydem/broadphase/cell_grid.h"
#include "polydem/broadphase/scene_bounds.h"
#include "polydem/core/error.h"

namespace polydem::broadphase {
namespace {

struct Set {
  std::vector<Vec3> centers;
  std::vector<double> radii;
  std::vector<Uid> uids;
  std::vector<std::uint8_t> active;
  SphereSet view() const { return {centers, radii, uids, active}; }
};

// `n` spheres of radius 0.5 at random in a 30 m box, in random order, then `ghosts` more.
Set randomSet(std::size_t n, std::size_t ghosts, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-3.0, 27.0);
  Set s;
  for (std::size_t i = 0; i < n + ghosts; ++i) {
    s.centers.emplace_back(u(rng), u(rng), u(rng));
    s.radii.push_back(0.5);
    s.uids.push_back(1000 + (i * 7919) % (n + ghosts));  // unique, not in index order
    s.active.push_back(i < n);
  }
  return s;
}

// The first `order.size()` entries of `s` in that order, the rest as they were.
Set permuted(const Set& s, std::span<const std::int32_t> order) {
  Set out = s;
  for (std::size_t k = 0; k < order.size(); ++k) {
    out.centers[k] = s.centers[order[k]];
    out.radii[k] = s.radii[order[k]];
    out.uids[k] = s.uids[order[k]];
    out.active[k] = s.active[order[k]];
  }
  return out;
}

TEST(CellOrder, AGridOfTheSameReachGathersTheSortedSetFrontToBack) {
  const std::size_t n = 3000;
  const Set set = randomSet(n, 400, 5);
  const double reach = 1.0 + 1e-3;
  CellOrder cells;
  const auto order = cells.order(set.view(), n, reach);
  ASSERT_EQ(order.size(), n);
  std::vector<std::int32_t> seen(order.begin(), order.end());
  std::sort(seen.begin(), seen.end());
  for (std::size_t k = 0; k < n; ++k) ASSERT_EQ(seen[k], static_cast<std::int32_t>(k));
  std::size_t moved = 0;
  for (std::size_t k = 0; k < n; ++k) moved += order[k] != static_cast<std::int32_t>(k);
  EXPECT_GT(moved, n / 2) << "a random set should not be in cell order already";

  const Set sorted = permuted(set, order);
  std::vector<std::int32_t> members(n);
  for (std::size_t i = 0; i < n; ++i) members[i] = static_cast<std::int32_t>(i);
  detail::CellGrid grid;
  grid.build(sorted.view(), members, reach, detail::checkAndBound(sorted.view(), 0.0), false);
  for (std::size_t p = 0; p < n; ++p) {
    ASSERT_EQ(grid.meta()[p].index, static_cast<std::int32_t>(p)) << "at grid position " << p;
  }
  // Sorting the sorted set changes nothing.
  CellOrder again;
  const auto second = again.order(sorted.view(), n, reach);
  for (std::size_t k = 0; k < n; ++k) ASSERT_EQ(second[k], static_cast<std::int32_t>(k));
}

TEST(CellOrder, CellsInZYXOrderTiesByIndex) {
  const std::size_t n = 5000;
  const Set set = randomSet(n, 0, 9);
  const double reach = 2.0;
  CellOrder cells;
  const auto order = cells.order(set.view(), n, reach);
  // Cell coordinates computed here from the lowest centre (the grid's edge exceeds the reach by
  // a relative 1e-12 or so; no random centre falls that close to a cell face).
  Vec3 lo = set.centers[0];
  for (const Vec3& c : set.centers) lo = lo.cwiseMin(c);
  auto cell = [&](std::int32_t i) {
    const Vec3 q = (set.centers[i] - lo) / reach;
    return std::array<double, 3>{std::floor(q.z()), std::floor(q.y()), std::floor(q.x())};
  };
  std::size_t ties = 0;
  for (std::size_t k = 1; k < n; ++k) {
    const auto a = cell(order[k - 1]), b = cell(order[k]);
    ASSERT_LE(a, b) << "cells out of (z, y, x) order at " << k;
    if (a == b) {
      ++ties;
      ASSERT_LT(order[k - 1], order[k]) << "members of one cell out of index order at " << k;
    }
  }
  EXPECT_GT(ties, n / 4) << "the scene should put several spheres in a cell";
}

TEST(CellOrder, NoAllocationOnceWarm) {
  const Set set = randomSet(2000, 100, 3);
  Set moved = set;
  for (Vec3& c : moved.centers) c.x() += 0.3;
  CellOrder cells;
  cells.order(set.view(), 2000, 1.0);
  cells.order(moved.view(), 2000, 1.0);
  const long before = polydem::testing::allocationCount();
  cells.order(set.view(), 2000, 1.0);
  cells.order(moved.view(), 1900, 1.0);
  EXPECT_EQ(polydem::testing::allocationCount() - before, 0);
}

TEST(CellOrder, RejectsBadArguments) {
  const Set set = randomSet(10, 0, 1);
  CellOrder cells;
  EXPECT_THROW(cells.order(set.view(), 11, 1.0), Error);
  EXPECT_THROW(cells.order(set.view(), 10, 0.0), Error);
  EXPECT_THROW(cells.order(set.view(), 10, std::nan("")), Error);
  EXPECT_EQ(cells.order(set.view(), 0, 1.0).size(), 0u);
}

}  // namespace
}  // namespace polydem::broadphase
