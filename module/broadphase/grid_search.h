// The two searches the grids are made for (internal): pairs among the members of one grid
// (Munjiza & Andrews' NBS: own cell plus the 13 "forward" neighbour cells, so each pair of cells
// is visited once), and pairs between the members of a grid of smaller particles and the members
// of a grid of larger ones (Zhao section 4, step k: the smaller groups are searched in the cells
// of group k).
#pragma once

#include <vector>

#include "polydem/broadphase/cell_grid.h"

namespace polydem::broadphase::detail {

/// Every pair of members of `grid` within reach. Needs grid.edge() >= 2 * maxRadius + margin.
void searchWithin(const CellGrid& grid, double margin, PairWriter& out);
/// The same pairs, written in a way that suits grids where few tests hit (cells much larger
/// than most members: NBS with mixed sizes).
void searchWithinSparse(const CellGrid& grid, double margin, PairWriter& out);

/// Every pair (q, t) within reach, q a member of `queries` and t a member of `target` (built
/// with lookup). Taken a run of cells of `queries` at a time: the target cells around the box of
/// the run's centres are looked up once (and reused while consecutive runs need the same ones),
/// their members are first tested against the box, and only the members that can reach it are
/// tested against each query of the run. `scratch` is kept by the caller between calls.
struct AcrossScratch {
  struct Range {
    std::int32_t begin, end;  // target members, contiguous
  };
  std::vector<Range> found;             // the members of the target cells looked up
  std::vector<std::int32_t> survivors;  // those that pass the box test
};
void searchAcross(const CellGrid& target, const CellGrid& queries, double margin, PairWriter& out,
                  AcrossScratch& scratch);

/// Same pairs as searchWithin / searchAcross, by testing every pair: cheaper than cells when the
/// grid has only a few members (a lone boundary block).
void searchWithinDirect(const CellGrid& grid, double margin, PairWriter& out);
void searchAcrossDirect(const CellGrid& target, const CellGrid& queries, double margin,
                        PairWriter& out);

}  // namespace polydem::broadphase::detail
