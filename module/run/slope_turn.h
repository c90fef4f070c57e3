// How a slope on a tilting platform fails, read as a property of the slope rather than of one
// block: the `tilt_failure` check's measure = "rotation". When the slope's first block has moved
// the check's reach against the platform, the blocks that have moved at least a tenth of that
// reach are the ones that fail; their mass-weighted median turn against the platform is near zero
// when they slide and large when they topple. The first block alone can mislead: on a toppling
// staircase of stacked cubes it is often a top cube sliding off its leaning column.
#pragma once

#include <vector>

namespace polydem::run {

/// One block's motion against the platform since the tilt started.
struct BlockMove {
  double displacement = 0.0;  // m, of its centroid
  double turn = 0.0;          // deg, of its orientation
  double mass = 0.0;          // kg: its weight in the median
};

/// The fraction of the check's reach a block must have moved to count in the slope's turn.
inline constexpr double kTurnMovedFraction = 0.1;

/// The mass-weighted median turn (deg) of the blocks that have moved at least `moved` (m): the
/// smallest turn at which the blocks turned no more than it hold half the moved mass. The same
/// value whatever the order of `blocks` (they are sorted). NaN when no block has moved `moved`.
double slopeTurn(std::vector<BlockMove> blocks, double moved);

}  // namespace polydem::run
