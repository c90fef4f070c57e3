// Block counts fitted to where the free particles are, not to the domain box.
//
// chooseBlockCounts cuts the domain box into about ranks * hint blocks. When the particles fill
// only part of the box (a pile on a floor much wider than it, a runout's source area in a large
// domain, a box inflated around fixed boundary bodies) most of those blocks are empty and the
// pile sits in a handful of blocks that no partition can share out: 4,000 cubes on a floor twice
// as wide all landed in one block of 2 ranks. fitBlockCounts instead sizes the blocks
// so that at least ranks * hint of them hold a free particle, which is what the balancer needs to
// share the load in whole blocks; fixed and driven bodies play no part.
#pragma once

#include <cstdint>
#include <functional>
#include <span>

#include "polydem/domain/aabb.h"
#include "polydem/domain/block_forest.h"

namespace polydem::domain {

struct BlockFitOptions {
  int ranks = 1;
  /// Occupied blocks wanted per rank: a rank's share of the load is made of whole blocks, so
  /// more blocks per rank give a finer balance (and more, thinner ghost layers between blocks).
  int occupied_per_rank = 16;
  /// No block edge shorter than this (e.g. a particle diameter): blocks below the size of a
  /// particle only multiply the ghost copies. 0 = no limit.
  double min_block_edge = 0.0;
  /// Upper limit on the number of blocks (every rank holds the whole block -> rank map).
  std::int64_t max_blocks = std::int64_t{1} << 21;
  /// The number of free particles, if known (0: not known): no more occupied blocks are wanted
  /// than one per 4 particles (at least one per rank), so that a few particles in a large domain
  /// do not ask for blocks of a particle's size all over it.
  std::int64_t particles = 0;
};

/// The number of blocks of the uniform grid `counts` over the domain that hold at least one free
/// particle centroid. Collective in a parallel run (every rank must get the same answer).
using OccupiedBlockCount = std::function<std::int64_t(const Index3& counts)>;

/// Block counts for `domain` such that at least ranks * occupied_per_rank blocks are occupied
/// (or the particles' limit above).
/// `particles` is the box the free particles fill (their centroids' bounding box inflated by
/// their circumradius); it decides the first block edge h: the edge for which about ranks *
/// occupied_per_rank cubes fill that box (axes thinner than h get one layer). The grid along axis
/// a has round(L_a / h) blocks (at least 1, and none shorter than min_block_edge); while fewer
/// blocks than wanted are occupied, h shrinks by 2^(1/3) (the block count doubles). It stops at
/// the first grid with enough occupied blocks, at min_block_edge, or before max_blocks. If the
/// result has fewer blocks than ranks, chooseBlockCounts(domain, ranks, 1) is returned instead.
/// Depends only on the proportions (scale-free) and on what `occupied` answers, so every rank
/// computes the same counts.
Index3 fitBlockCounts(const Aabb& domain, const Aabb& particles, const BlockFitOptions& options,
                      const OccupiedBlockCount& occupied);

/// Occupied blocks of the grid `counts` over `domain` for a set of points held by one process
/// (points outside the domain are ignored).
std::int64_t countOccupiedBlocks(const Aabb& domain, const Index3& counts, const Periodic& periodic,
                                 std::span<const Vec3> points);

}  // namespace polydem::domain
