#include "polydem/broadphase/grid_search.h"

#include <algorithm>
#include <bit>

#include "polydem/broadphase/overlap.h"

namespace polydem::broadphase::detail {

namespace {

inline bool near(const Item& a, const Item& b, double margin) {
  return withinReach(a.x, a.y, a.z, a.r, b.x, b.y, b.z, b.r, margin);
}

// Tests item a against the contiguous items [begin, end) of the same arrays or others and writes
// the pairs found. Two ways, the same pairs in the same order:
//  - kWritePerTest: every test writes its pair and the end advances by the outcome, with no
//    branch at all: best where a fair share of the tests hit (the multi-level grids, whose cells
//    fit their members: about one test in four);
//  - kMaskPerBlock: each block of 64 is tested into a bit mask, then only the hits are written:
//    best where hits are rare (NBS cells sized for the largest member: one test in fifty).
// A mispredicted branch on a test's outcome (hard to predict: a third hit among neighbours of one
// size) costs more than either.
enum class Emit { kWritePerTest, kMaskPerBlock };

template <Emit kEmit>
inline void testRange(const Item& a, const Meta& a_meta, const Item* items, const Meta* meta,
                      std::int32_t begin, std::int32_t end, double margin, PairWriter& out) {
  if (begin >= end) return;
  CandidatePair* w = out.room(static_cast<std::size_t>(end - begin));
  if constexpr (kEmit == Emit::kWritePerTest) {
    for (std::int32_t k = begin; k < end; ++k) {
      w = writePair(a_meta, meta[k], near(a, items[k], margin), w);
    }
  } else {
    for (std::int32_t block = begin; block < end; block += 64) {
      const std::int32_t n = std::min<std::int32_t>(64, end - block);
      std::uint64_t hits = 0;
      for (std::int32_t k = 0; k < n; ++k) {
        hits |= static_cast<std::uint64_t>(near(a, items[block + k], margin)) << k;
      }
      for (; hits != 0; hits &= hits - 1) {
        w = writePair(a_meta, meta[block + std::countr_zero(hits)], true, w);
      }
    }
  }
  out.keep(w);
}

// Whether a sphere (centre t, radius t.r) can be within reach of any sphere of radius <= r_max
// centred in the box [lo, hi]. Never false when withinReach() would be true for such a sphere:
// each term below is, in floating point, at most the corresponding term of withinReach().
inline bool boxWithinReach(const Item& t, const Vec3& lo, const Vec3& hi, double r_max,
                           double margin) {
  // Distance to the box along each axis (0 inside); max() compiles to branch-free maxsd.
  const double dx = std::max(std::max(lo.x() - t.x, t.x - hi.x()), 0.0);
  const double dy = std::max(std::max(lo.y() - t.y, t.y - hi.y()), 0.0);
  const double dz = std::max(std::max(lo.z() - t.z, t.z - hi.z()), 0.0);
  const double reach = r_max + t.r + margin;
  return dx * dx + dy * dy + dz * dz <= reach * reach;
}

// Advances `cursor` to the first cell at or after `from` and returns the end of the run of
// cells in the same row as `from` with x <= x_last.
inline std::size_t rowRun(std::span<const CellGrid::Cell> cells, const CellKey& from,
                          std::int64_t x_last, std::size_t& cursor) {
  while (cursor < cells.size() && cellBefore(cells[cursor].key, from)) ++cursor;
  std::size_t end = cursor;
  while (end < cells.size() && cells[end].key.z == from.z && cells[end].key.y == from.y &&
         cells[end].key.x <= x_last) {
    ++end;
  }
  return end;
}

// The neighbour rows (dy, dz) after the own row in (z, y, x) order; with the own cell and its
// +x neighbour they are Munjiza & Andrews' 13 forward neighbours: each x run spans dx = -1..1.
// For a fixed row offset the rows wanted by cells taken in (z, y, x) order come in (z, y, x)
// order too, so one cursor per offset walks the cell array once: no search, no hashing.
constexpr std::int64_t kForwardRows[4][2] = {{1, 0}, {-1, 1}, {0, 1}, {1, 1}};

template <Emit kEmit>
void searchWithinCells(const CellGrid& grid, double margin, PairWriter& out) {
  const Item* items = grid.items().data();
  const Meta* meta = grid.meta().data();
  const auto cells = grid.cells();
  std::size_t cursor[4] = {0, 0, 0, 0};
  for (std::size_t c = 0; c < cells.size(); ++c) {
    const CellGrid::Cell& cell = cells[c];
    const CellKey& key = cell.key;
    // Own cell, and the +x neighbour, which is the next cell if it exists: one contiguous block.
    std::int32_t block_end = cell.end;
    if (c + 1 < cells.size() && cells[c + 1].key == CellKey{key.x + 1, key.y, key.z}) {
      block_end = cells[c + 1].end;
    }
    for (std::int32_t a = cell.begin; a < cell.end; ++a) {
      testRange<kEmit>(items[a], meta[a], items, meta, a + 1, block_end, margin, out);
    }
    for (std::size_t r = 0; r < 4; ++r) {
      const CellKey from{key.x - 1, key.y + kForwardRows[r][0], key.z + kForwardRows[r][1]};
      const std::size_t end = rowRun(cells, from, key.x + 1, cursor[r]);
      if (end == cursor[r]) continue;
      const std::int32_t begin = cells[cursor[r]].begin, stop = cells[end - 1].end;
      for (std::int32_t a = cell.begin; a < cell.end; ++a) {
        testRange<kEmit>(items[a], meta[a], items, meta, begin, stop, margin, out);
      }
    }
  }
}

}  // namespace

void searchWithin(const CellGrid& grid, double margin, PairWriter& out) {
  searchWithinCells<Emit::kWritePerTest>(grid, margin, out);
}

void searchWithinSparse(const CellGrid& grid, double margin, PairWriter& out) {
  searchWithinCells<Emit::kMaskPerBlock>(grid, margin, out);
}

void searchAcross(const CellGrid& target, const CellGrid& queries, double margin, PairWriter& out,
                  AcrossScratch& scratch) {
  std::vector<std::int32_t>& found = scratch.found;
  std::vector<std::int32_t>& survivors = scratch.survivors;
  const Item* titems = target.items().data();
  const Meta* tmeta = target.meta().data();
  const auto tcells = target.cells();
  const Item* qitems = queries.items().data();
  const Meta* qmeta = queries.meta().data();
  const double reach_to_target = target.maxRadius() + margin;

  CellKey last_lo{1, 1, 1}, last_hi{0, 0, 0};  // an empty box: no query cell matches it
  found.clear();
  for (const CellGrid::Cell& qcell : queries.cells()) {
    // The box of the query centres of this cell and their largest radius.
    Vec3 lo(qitems[qcell.begin].x, qitems[qcell.begin].y, qitems[qcell.begin].z), hi = lo;
    double r_max = 0.0;
    for (std::int32_t q = qcell.begin; q < qcell.end; ++q) {
      const Item& item = qitems[q];
      lo = lo.cwiseMin(Vec3(item.x, item.y, item.z));
      hi = hi.cwiseMax(Vec3(item.x, item.y, item.z));
      r_max = std::max(r_max, item.r);
    }
    CellKey klo, khi;
    target.keysAround(lo, hi, r_max + reach_to_target, klo, khi);
    if (!(klo == last_lo && khi == last_hi)) {
      // The target members in those cells, in one list.
      found.clear();
      for (std::int64_t z = klo.z; z <= khi.z; ++z) {
        for (std::int64_t y = klo.y; y <= khi.y; ++y) {
          for (std::int64_t x = klo.x; x <= khi.x; ++x) {
            const std::int32_t c = target.find({x, y, z});
            if (c < 0) continue;
            for (std::int32_t t = tcells[c].begin; t < tcells[c].end; ++t) found.push_back(t);
          }
        }
      }
      last_lo = klo;
      last_hi = khi;
      survivors.resize(found.size());
    }
    // Members that can reach the cell's box, kept without a branch on the outcome.
    std::size_t kept = 0;
    for (const std::int32_t t : found) {
      survivors[kept] = t;
      kept += static_cast<std::size_t>(boxWithinReach(titems[t], lo, hi, r_max, margin));
    }
    for (std::size_t k = 0; k < kept; ++k) {
      const std::int32_t t = survivors[k];
      testRange<Emit::kWritePerTest>(titems[t], tmeta[t], qitems, qmeta, qcell.begin, qcell.end,
                                     margin, out);
    }
  }
}

void searchWithinDirect(const CellGrid& grid, double margin, PairWriter& out) {
  const auto n = static_cast<std::int32_t>(grid.items().size());
  for (std::int32_t a = 0; a < n; ++a) {
    testRange<Emit::kWritePerTest>(grid.items()[a], grid.meta()[a], grid.items().data(),
                                   grid.meta().data(), a + 1, n, margin, out);
  }
}

void searchAcrossDirect(const CellGrid& target, const CellGrid& queries, double margin,
                        PairWriter& out) {
  const auto n = static_cast<std::int32_t>(queries.items().size());
  for (std::size_t t = 0; t < target.items().size(); ++t) {
    testRange<Emit::kWritePerTest>(target.items()[t], target.meta()[t], queries.items().data(),
                                   queries.meta().data(), 0, n, margin, out);
  }
}

}  // namespace polydem::broadphase::detail
