#include "polydem/run/slope_turn.h"

#include <algorithm>
#include <limits>
#include <tuple>

namespace polydem::run {

double slopeTurn(std::vector<BlockMove> blocks, double moved) {
  std::erase_if(blocks, [moved](const BlockMove& b) { return !(b.displacement >= moved); });
  if (blocks.empty()) return std::numeric_limits<double>::quiet_NaN();
  // A total order (turn first): the same median from blocks gathered in any rank order.
  std::sort(blocks.begin(), blocks.end(), [](const BlockMove& a, const BlockMove& b) {
    return std::tie(a.turn, a.displacement, a.mass) < std::tie(b.turn, b.displacement, b.mass);
  });
  double total = 0.0;
  for (const BlockMove& b : blocks) total += b.mass;
  double below = 0.0;
  for (const BlockMove& b : blocks) {
    below += b.mass;
    if (below >= 0.5 * total) return b.turn;
  }
  return blocks.back().turn;
}

}  // namespace polydem::run
