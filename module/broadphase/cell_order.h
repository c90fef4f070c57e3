// The order in which the broad phase's grids visit space, as an order for particle storage.
//
// A grid (cell_grid.h) gathers its members' centres and radii in cell order, (z, y, x), and its
// searches then read them from its own arrays. When the storage is in creation or arrival order,
// that gather reads the SphereSet in no order at all: past the caches every member costs up to
// four misses, and so does every later loop that runs over the pairs and touches both particles.
// Particle codes therefore reorder their storage along space from time to time (LAMMPS's atom
// sort, waLBerla, ExaDEM). CellOrder gives that order: the first `count` entries of a SphereSet
// sorted as a grid of the given reach over the bounds of the whole set sorts them (the same edge,
// origin, rounding slack and tie rule: by index within a cell), so that storage permuted by it is
// gathered front to back by a grid of that reach over the same set.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "polydem/broadphase/broad_phase.h"
#include "polydem/broadphase/cell_grid.h"

namespace polydem::broadphase {

class CellOrder {
 public:
  /// Indices [0, count) of `spheres` in (z, y, x) order of cells of edge >= `reach` (as
  /// CellGrid::build makes them over the bounds of all of `spheres`), ties by index. `reach` > 0.
  /// The span stays valid until the next call. No allocation once warm. Throws polydem::Error for
  /// the inputs BroadPhase::findPairs rejects, and for count > spheres.centers.size().
  std::span<const std::int32_t> order(const SphereSet& spheres, std::size_t count, double reach);
  /// Heap bytes of its grid and index arrays (capacities, core/memory.h).
  std::uint64_t heapBytes() const;

 private:
  detail::CellGrid grid_;
  std::vector<std::int32_t> members_, order_;
};

}  // namespace polydem::broadphase
