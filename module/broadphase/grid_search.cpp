#include "broadphase/grid_search.h"

#include "broadphase/overlap.h"

namespace polydem::broadphase::detail {

namespace {

inline bool near(const Item& a, const Item& b, double margin) {
  return withinReach(a.x, a.y, a.z, a.r, b.x, b.y, b.z, b.r, margin);
}

// The 13 neighbour offsets (dx, dy, dz) that come after (0, 0, 0) in (z, y, x) order: with the
// own cell they visit each unordered pair of adjacent cells exactly once (Munjiza & Andrews).
constexpr std::int64_t kForward[13][3] = {
    {1, 0, 0},  {-1, 1, 0}, {0, 1, 0}, {1, 1, 0},  {-1, -1, 1}, {0, -1, 1}, {1, -1, 1},
    {-1, 0, 1}, {0, 0, 1},  {1, 0, 1}, {-1, 1, 1}, {0, 1, 1},   {1, 1, 1}};

}  // namespace

void searchWithin(const CellGrid& grid, const SphereSet& spheres, double margin,
                  std::vector<CandidatePair>& out) {
  const Item* items = grid.items().data();
  const std::int32_t* index = grid.index().data();
  const auto cells = grid.cells();
  for (const CellGrid::Cell& cell : cells) {
    for (std::int32_t a = cell.begin; a < cell.end; ++a) {
      for (std::int32_t b = a + 1; b < cell.end; ++b) {
        if (near(items[a], items[b], margin)) emitPair(spheres, index[a], index[b], out);
      }
    }
    for (const auto& off : kForward) {
      const std::int32_t other =
          grid.find({cell.key.x + off[0], cell.key.y + off[1], cell.key.z + off[2]});
      if (other < 0) continue;
      const CellGrid::Cell& nb = cells[other];
      for (std::int32_t a = cell.begin; a < cell.end; ++a) {
        for (std::int32_t b = nb.begin; b < nb.end; ++b) {
          if (near(items[a], items[b], margin)) emitPair(spheres, index[a], index[b], out);
        }
      }
    }
  }
}

void searchAcross(const CellGrid& target, const CellGrid& queries, const SphereSet& spheres,
                  double margin, std::vector<CandidatePair>& out,
                  std::vector<std::pair<std::int32_t, std::int32_t>>& ranges) {
  const Item* titems = target.items().data();
  const std::int32_t* tindex = target.index().data();
  const auto tcells = target.cells();
  const auto qitems = queries.items();
  const std::int32_t* qindex = queries.index().data();
  const double reach_to_target = target.maxRadius() + margin;

  CellKey last_lo{1, 1, 1}, last_hi{0, 0, 0};  // an empty box: no query matches it
  ranges.clear();
  ranges.reserve(64);  // boxes of queries smaller than the targets touch at most 27 cells
  for (std::size_t q = 0; q < qitems.size(); ++q) {
    const Item& item = qitems[q];
    CellKey lo, hi;
    target.boxAround(item.x, item.y, item.z, item.r + reach_to_target, lo, hi);
    if (!(lo == last_lo && hi == last_hi)) {
      ranges.clear();
      for (std::int64_t z = lo.z; z <= hi.z; ++z) {
        for (std::int64_t y = lo.y; y <= hi.y; ++y) {
          for (std::int64_t x = lo.x; x <= hi.x; ++x) {
            const std::int32_t c = target.find({x, y, z});
            if (c >= 0) ranges.emplace_back(tcells[c].begin, tcells[c].end);
          }
        }
      }
      last_lo = lo;
      last_hi = hi;
    }
    for (const auto& [begin, end] : ranges) {
      for (std::int32_t t = begin; t < end; ++t) {
        if (near(item, titems[t], margin)) emitPair(spheres, qindex[q], tindex[t], out);
      }
    }
  }
}

void searchWithinDirect(const CellGrid& grid, const SphereSet& spheres, double margin,
                        std::vector<CandidatePair>& out) {
  const auto items = grid.items();
  const std::int32_t* index = grid.index().data();
  const auto n = static_cast<std::int32_t>(items.size());
  for (std::int32_t a = 0; a < n; ++a) {
    for (std::int32_t b = a + 1; b < n; ++b) {
      if (near(items[a], items[b], margin)) emitPair(spheres, index[a], index[b], out);
    }
  }
}

void searchAcrossDirect(const CellGrid& target, const CellGrid& queries, const SphereSet& spheres,
                        double margin, std::vector<CandidatePair>& out) {
  const auto titems = target.items();
  const auto qitems = queries.items();
  for (std::size_t q = 0; q < qitems.size(); ++q) {
    for (std::size_t t = 0; t < titems.size(); ++t) {
      if (near(qitems[q], titems[t], margin)) {
        emitPair(spheres, queries.index()[q], target.index()[t], out);
      }
    }
  }
}

}  // namespace polydem::broadphase::detail
