#include "polydem/broadphase/grid_search.h"

#include <algorithm>
#include <bit>

#include "polydem/broadphase/sphere_tests.h"

namespace polydem::broadphase::detail {

namespace {

// Tests member a (at position a_pos of its grid) against the contiguous members [begin, end)
// of the same grid or another one and writes the positions (a_pos, k) of the pairs found, to be
// resolved later (PairWriter::resolve). Two ways, the same pairs in the same order:
//  - kWritePerTest: Lanes::kLanes members at a time (sphere_tests.h); each writes its pair and the
//    end advances by the outcome, with no branch at all: best where a fair share of the tests
//    hit (the multi-level grids, whose cells fit their members: about one test in six);
//  - kMaskPerBlock: each block of 64 is tested (kLanes at a time) into a bit mask, then only the
//    hits are written: best where hits are rare (NBS cells sized for the largest member: one
//    test in fifty).
// A mispredicted branch on a test's outcome (hard to predict: a third hit among neighbours of one
// size) costs more than either. Lanes past `end` read the next cell or the padding (kPad).
//
// The searches below are templates on Lanes, always inlined, so that the four-lane versions are
// compiled as a whole inside the entry points compiled for AVX2 (at the end of this file).
enum class Emit { kWritePerTest, kMaskPerBlock };

template <Emit kEmit, class Lanes>
[[gnu::always_inline]] inline void testRange(const Probe& a, std::int32_t a_pos, const Coords& b,
                                             std::int32_t begin, std::int32_t end, double margin,
                                             PairWriter& out) {
  constexpr std::int32_t kLanes = Lanes::kLanes;
  if (begin >= end) return;
  CandidatePair* w = out.room(static_cast<std::size_t>(end - begin) + kLanes - 1);
  if constexpr (kEmit == Emit::kWritePerTest && kLanes == 2) {
    std::uint32_t last = 0;
    for (std::int32_t k = begin; k < end; k += 2) {
      const std::uint32_t hits = Lanes::near(a, b, k, margin);
      *w = {a_pos, k};
      w += hits & 1u;
      *w = {a_pos, k + 1};
      last = hits >> 1;
      w += last;
    }
    // For an odd count the last lane lay past the range (next cell or padding): drop its pair,
    // the last one written.
    w -= last & static_cast<std::uint32_t>(end - begin);
  } else if constexpr (kEmit == Emit::kWritePerTest) {
    for (std::int32_t k = begin; k < end; k += kLanes) {
      // Lanes past the range (the last group only) are masked off.
      const std::int32_t valid = std::min(end - k, kLanes);
      const std::uint32_t hits = Lanes::near(a, b, k, margin) & ((1u << valid) - 1u);
      w = Lanes::writeHits(w, a_pos, k, hits);
    }
  } else {
    for (std::int32_t block = begin; block < end; block += 64) {
      const std::int32_t n = std::min<std::int32_t>(64, end - block);
      std::uint64_t hits = 0;
      for (std::int32_t k = 0; k < n; k += kLanes) {
        hits |= static_cast<std::uint64_t>(Lanes::near(a, b, block + k, margin)) << k;
      }
      // Lanes past the block (n not a multiple of kLanes) are dropped.
      hits &= n == 64 ? ~std::uint64_t{0} : (std::uint64_t{1} << n) - 1;
      for (; hits != 0; hits &= hits - 1) {
        *w++ = {a_pos, block + std::countr_zero(hits)};
      }
    }
  }
  out.keep(w);
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

template <Emit kEmit, class Lanes>
[[gnu::always_inline]] inline void searchWithinCells(const CellGrid& grid, double margin,
                                                     PairWriter& out) {
  const Coords coords = grid.coords();
  const Meta* meta = grid.meta().data();
  const auto cells = grid.cells();
  std::size_t cursor[4] = {0, 0, 0, 0};
  for (std::size_t c = 0; c < cells.size(); ++c) {
    const CellGrid::Cell& cell = cells[c];
    const CellKey& key = cell.key;
    const std::size_t first_pair = out.mark();
    // Own cell, and the +x neighbour, which is the next cell if it exists: one contiguous block.
    std::int32_t block_end = cell.end;
    if (c + 1 < cells.size() && cells[c + 1].key == CellKey{key.x + 1, key.y, key.z}) {
      block_end = cells[c + 1].end;
    }
    for (std::int32_t a = cell.begin; a < cell.end; ++a) {
      testRange<kEmit, Lanes>(probeOf(coords, a), a, coords, a + 1, block_end, margin, out);
    }
    for (std::size_t r = 0; r < 4; ++r) {
      const CellKey from{key.x - 1, key.y + kForwardRows[r][0], key.z + kForwardRows[r][1]};
      const std::size_t end = rowRun(cells, from, key.x + 1, cursor[r]);
      if (end == cursor[r]) continue;
      const std::int32_t begin = cells[cursor[r]].begin, stop = cells[end - 1].end;
      for (std::int32_t a = cell.begin; a < cell.end; ++a) {
        testRange<kEmit, Lanes>(probeOf(coords, a), a, coords, begin, stop, margin, out);
      }
    }
    out.resolve(first_pair, meta, meta);  // while this cell's members are in the cache
  }
}

template <class Lanes>
[[gnu::always_inline]] inline void searchAcrossRuns(const CellGrid& target, const CellGrid& queries,
                                                    double margin, PairWriter& out,
                                                    AcrossScratch& scratch) {
  std::vector<AcrossScratch::Range>& found = scratch.found;
  std::vector<std::int32_t>& survivors = scratch.survivors;
  constexpr std::int32_t kLanes = Lanes::kLanes;
  const Coords tcoords = target.coords();
  const Meta* tmeta = target.meta().data();
  const auto tcells = target.cells();
  const Coords qcoords = queries.coords();
  const Meta* qmeta = queries.meta().data();
  const double reach_to_target = target.maxRadius() + margin;

  // Query cells are taken in runs of cells of one row (contiguous in memory) at most `span`
  // cells wide, so that one box test per target member serves several small cells. A run spans
  // at most half a target cell, so its box lets through at most about 1.5 times the target
  // members a single cell's would per query (the reach, about a target cell, grows by half).
  const double cells_per_half_target = 0.5 * target.edge() / queries.edge();
  const auto span = static_cast<std::int64_t>(std::clamp(cells_per_half_target, 1.0, 1e6));
  const auto qcells = queries.cells();
  CellKey last_lo{1, 1, 1}, last_hi{0, 0, 0};  // an empty box: no query run matches it
  found.clear();
  for (std::size_t run = 0, run_end = 0; run < qcells.size(); run = run_end) {
    const CellKey& first = qcells[run].key;
    for (run_end = run + 1; run_end < qcells.size(); ++run_end) {
      const CellKey& key = qcells[run_end].key;
      if (key.z != first.z || key.y != first.y || key.x - first.x >= span) break;
    }
    const std::int32_t qbegin = qcells[run].begin, qend = qcells[run_end - 1].end;
    const std::size_t first_pair = out.mark();
    // The box of the run's query centres and their largest radius.
    Vec3 lo(qcoords.x[qbegin], qcoords.y[qbegin], qcoords.z[qbegin]), hi = lo;
    double r_max = 0.0;
    for (std::int32_t q = qbegin; q < qend; ++q) {
      const Vec3 centre(qcoords.x[q], qcoords.y[q], qcoords.z[q]);
      lo = lo.cwiseMin(centre);
      hi = hi.cwiseMax(centre);
      r_max = std::max(r_max, qcoords.r[q]);
    }
    CellKey klo, khi;
    target.keysAround(lo, hi, r_max + reach_to_target, klo, khi);
    if (!(klo == last_lo && khi == last_hi)) {
      // The target members in those cells, as ranges (cells adjacent in memory merged).
      found.clear();
      std::size_t members = 0;
      for (std::int64_t z = klo.z; z <= khi.z; ++z) {
        for (std::int64_t y = klo.y; y <= khi.y; ++y) {
          for (std::int64_t x = klo.x; x <= khi.x; ++x) {
            const std::int32_t c = target.find({x, y, z});
            if (c < 0) continue;
            members += static_cast<std::size_t>(tcells[c].end - tcells[c].begin);
            if (!found.empty() && found.back().end == tcells[c].begin) {
              found.back().end = tcells[c].end;
            } else {
              found.push_back({tcells[c].begin, tcells[c].end});
            }
          }
        }
      }
      last_lo = klo;
      last_hi = khi;
      survivors.resize(members + kLanes - 1);  // the last lanes of a range write past it
    }
    // Members that can reach the run's box, in the order of `found`, kept without a branch on
    // the outcome; lanes past a range are masked off.
    const QueryBox box{{lo.x(), lo.y(), lo.z()}, {hi.x(), hi.y(), hi.z()}, r_max};
    std::size_t kept = 0;
    for (const AcrossScratch::Range& range : found) {
      for (std::int32_t t = range.begin; t < range.end; t += kLanes) {
        const std::int32_t valid = std::min(range.end - t, kLanes);
        const std::uint32_t hits = Lanes::nearBox(tcoords, t, box, margin) & ((1u << valid) - 1u);
        for (std::int32_t l = 0; l < kLanes; ++l) {
          survivors[kept] = t + l;
          kept += (hits >> l) & 1u;
        }
      }
    }
    for (std::size_t k = 0; k < kept; ++k) {
      const std::int32_t t = survivors[k];
      testRange<Emit::kWritePerTest, Lanes>(probeOf(tcoords, t), t, qcoords, qbegin, qend, margin,
                                            out);
    }
    out.resolve(first_pair, tmeta, qmeta);
  }
}

template <class Lanes>
[[gnu::always_inline]] inline void searchWithinAll(const CellGrid& grid, double margin,
                                                   PairWriter& out) {
  const auto n = static_cast<std::int32_t>(grid.size());
  const Coords coords = grid.coords();
  const std::size_t first_pair = out.mark();
  for (std::int32_t a = 0; a < n; ++a) {
    testRange<Emit::kWritePerTest, Lanes>(probeOf(coords, a), a, coords, a + 1, n, margin, out);
  }
  out.resolve(first_pair, grid.meta().data(), grid.meta().data());
}

template <class Lanes>
[[gnu::always_inline]] inline void searchAcrossAll(const CellGrid& target, const CellGrid& queries,
                                                   double margin, PairWriter& out) {
  const auto n = static_cast<std::int32_t>(queries.size());
  const Coords tcoords = target.coords();
  const std::size_t first_pair = out.mark();
  for (std::int32_t t = 0; t < static_cast<std::int32_t>(target.size()); ++t) {
    testRange<Emit::kWritePerTest, Lanes>(probeOf(tcoords, t), t, queries.coords(), 0, n, margin,
                                          out);
  }
  out.resolve(first_pair, target.meta().data(), queries.meta().data());
}

#if POLYDEM_BROADPHASE_AVX2
// The four-lane searches, compiled for AVX2 as a whole (the templates above are inlined here).
// Called only where testLanes() is kFour, which needs a CPU with AVX2.
[[gnu::target("avx2")]] void searchWithinFour(const CellGrid& grid, double margin,
                                              PairWriter& out) {
  searchWithinCells<Emit::kWritePerTest, FourLanes>(grid, margin, out);
}
[[gnu::target("avx2")]] void searchWithinSparseFour(const CellGrid& grid, double margin,
                                                    PairWriter& out) {
  searchWithinCells<Emit::kMaskPerBlock, FourLanes>(grid, margin, out);
}
[[gnu::target("avx2")]] void searchAcrossFour(const CellGrid& target, const CellGrid& queries,
                                              double margin, PairWriter& out,
                                              AcrossScratch& scratch) {
  searchAcrossRuns<FourLanes>(target, queries, margin, out, scratch);
}
[[gnu::target("avx2")]] void searchWithinDirectFour(const CellGrid& grid, double margin,
                                                    PairWriter& out) {
  searchWithinAll<FourLanes>(grid, margin, out);
}
[[gnu::target("avx2")]] void searchAcrossDirectFour(const CellGrid& target, const CellGrid& queries,
                                                    double margin, PairWriter& out) {
  searchAcrossAll<FourLanes>(target, queries, margin, out);
}
#endif

bool fourLanes() {
#if POLYDEM_BROADPHASE_AVX2
  return testLanes() == TestLanes::kFour;
#else
  return false;
#endif
}

}  // namespace

void searchWithin(const CellGrid& grid, double margin, PairWriter& out) {
#if POLYDEM_BROADPHASE_AVX2
  if (fourLanes()) return searchWithinFour(grid, margin, out);
#endif
  searchWithinCells<Emit::kWritePerTest, TwoLanes>(grid, margin, out);
}

void searchWithinSparse(const CellGrid& grid, double margin, PairWriter& out) {
#if POLYDEM_BROADPHASE_AVX2
  if (fourLanes()) return searchWithinSparseFour(grid, margin, out);
#endif
  searchWithinCells<Emit::kMaskPerBlock, TwoLanes>(grid, margin, out);
}

void searchAcross(const CellGrid& target, const CellGrid& queries, double margin, PairWriter& out,
                  AcrossScratch& scratch) {
#if POLYDEM_BROADPHASE_AVX2
  if (fourLanes()) return searchAcrossFour(target, queries, margin, out, scratch);
#endif
  searchAcrossRuns<TwoLanes>(target, queries, margin, out, scratch);
}

void searchWithinDirect(const CellGrid& grid, double margin, PairWriter& out) {
#if POLYDEM_BROADPHASE_AVX2
  if (fourLanes()) return searchWithinDirectFour(grid, margin, out);
#endif
  searchWithinAll<TwoLanes>(grid, margin, out);
}

void searchAcrossDirect(const CellGrid& target, const CellGrid& queries, double margin,
                        PairWriter& out) {
#if POLYDEM_BROADPHASE_AVX2
  if (fourLanes()) return searchAcrossDirectFour(target, queries, margin, out);
#endif
  searchAcrossAll<TwoLanes>(target, queries, margin, out);
}

}  // namespace polydem::broadphase::detail
