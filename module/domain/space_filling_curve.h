// Space-filling curves over block coordinates: the order in which partitionSfc deals out blocks.
#pragma once

#include <cstdint>
#include <vector>

#include "polydem/domain/block_forest.h"

namespace polydem::domain {

enum class Curve {
  kMorton,   ///< Z-order: bit interleaving; cheap, but jumps between distant blocks
  kHilbert,  ///< Hilbert order: consecutive cells are face neighbours, so chunks stay compact
};

/// Morton key of cell `c` in a 2^bits cube: bits of x, y, z interleaved (x lowest). bits <= 21.
std::uint64_t mortonKey(const Index3& c, int bits);
/// Hilbert key of cell `c` in a 2^bits cube (J. Skilling, "Programming the Hilbert curve", AIP
/// Conf. Proc. 707, 2004: axes -> transposed index -> interleaved bits). bits <= 21.
std::uint64_t hilbertKey(const Index3& c, int bits);
/// Bits per axis of the smallest power-of-two cube holding the forest's block grid (>= 1).
int curveBits(const BlockForest& forest);
/// All blocks of the forest sorted by their key on `curve` (the curve of the enclosing
/// power-of-two cube, with cells outside the grid skipped).
std::vector<int> sfcOrder(const BlockForest& forest, Curve curve);

}  // namespace polydem::domain
