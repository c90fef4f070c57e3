#include "polydem/broadphase/cell_order.h"

#include <cmath>

#include "polydem/broadphase/scene_bounds.h"
#include "polydem/core/error.h"
#include "polydem/core/memory.h"
#include "polydem/core/strings.h"

namespace polydem::broadphase {

std::span<const std::int32_t> CellOrder::order(const SphereSet& spheres, std::size_t count,
                                               double reach) {
  if (count > spheres.centers.size()) {
    throw Error(cat("cell order: ", count, " members of a set of ", spheres.centers.size()));
  }
  if (!(reach > 0.0) || !std::isfinite(reach)) {
    throw Error(cat("cell order: reach ", reach, " must be finite and > 0"));
  }
  const detail::SceneBounds bounds = detail::checkAndBound(spheres, 0.0);
  members_.resize(count);
  for (std::size_t i = 0; i < count; ++i) members_[i] = static_cast<std::int32_t>(i);
  // The grid's own sort: its radix sort, or its insertion sort from the last call's order, which
  // gives the radix sort's order too (after a reorder that last order names other particles, and
  // the insertion sort soon hands over).
  grid_.build(spheres, members_, reach, bounds, false);
  order_.resize(count);
  const auto meta = grid_.meta();
  for (std::size_t p = 0; p < count; ++p) order_[p] = meta[p].index;
  return order_;
}

std::uint64_t CellOrder::heapBytes() const {
  return grid_.heapBytes() + capacityBytes(members_) + capacityBytes(order_);
}

}  // namespace polydem::broadphase
