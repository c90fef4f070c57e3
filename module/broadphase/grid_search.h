// The two searches the grids are made for (internal): pairs among the members of one grid
// (Munjiza & Andrews' NBS: own cell plus the 13 "forward" neighbour cells, so each pair of cells
// is visited once), and pairs between the members of a grid of small spheres and the members of a
// grid of larger ones (Zhao section 4, step k: the smaller groups are searched in the cells of
// group k).
#pragma once

#include <utility>
#include <vector>

#include "broadphase/cell_grid.h"

namespace polydem::broadphase::detail {

/// Every pair of members of `grid` within reach. Needs grid.edge() >= 2 * maxRadius + margin.
void searchWithin(const CellGrid& grid, const SphereSet& spheres, double margin,
                  std::vector<CandidatePair>& out);

/// Every pair (q, t), q a member of `queries` and t a member of `target`, within reach. Each
/// query visits only the target cells that its reach box (radius r_q + target.maxRadius() +
/// margin) overlaps: for queries much smaller than the target's members that is 2 x 2 x 2 cells
/// instead of NBS's 27. Queries are taken in their own grid's cell order, so consecutive queries
/// usually share the box and its looked-up cells (`ranges` is scratch space kept by the caller).
void searchAcross(const CellGrid& target, const CellGrid& queries, const SphereSet& spheres,
                  double margin, std::vector<CandidatePair>& out,
                  std::vector<std::pair<std::int32_t, std::int32_t>>& ranges);

/// Same pairs as searchWithin / searchAcross, by testing every pair: cheaper than cell lookups
/// when a grid has only a few members (a lone boundary block).
void searchWithinDirect(const CellGrid& grid, const SphereSet& spheres, double margin,
                        std::vector<CandidatePair>& out);
void searchAcrossDirect(const CellGrid& target, const CellGrid& queries, const SphereSet& spheres,
                        double margin, std::vector<CandidatePair>& out);

}  // namespace polydem::broadphase::detail
