#include "broadphase/cell_grid.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>

namespace polydem::broadphase::detail {

namespace {
constexpr double kEps = std::numeric_limits<double>::epsilon();
}  // namespace

std::int64_t CellGrid::coord(double offset) const {
  return static_cast<std::int64_t>(std::floor(offset * inv_edge_));
}

std::int32_t CellGrid::findOrInsert(const CellKey& key) {
  for (std::uint64_t slot = hash(key) & mask_;; slot = (slot + 1) & mask_) {
    Slot& s = table_[slot];
    if (s.cell < 0) {
      s.key = key;
      s.cell = static_cast<std::int32_t>(cells_.size());
      cells_.push_back({key, 0, 0});
      return s.cell;
    }
    if (s.key == key) return s.cell;
  }
}

void CellGrid::build(const SphereSet& spheres, std::span<const std::int32_t> members, double reach,
                     const SceneBounds& bounds) {
  const auto n = static_cast<std::int32_t>(members.size());
  max_radius_ = 0.0;
  for (const std::int32_t m : members) max_radius_ = std::max(max_radius_, spheres.radii[m]);

  // Edge: at least the reach, never so small that the cell coordinates of the scene overflow,
  // and enlarged by the rounding slack of (x - x0) * (1 / edge) over the whole extent (a centre
  // is at most `cells_across` cells from the origin, each product has 3 roundings).
  origin_ = bounds.lo;
  const double extent = bounds.extent();
  const double base =
      std::max({reach, std::ldexp(extent, -50), std::numeric_limits<double>::min()});
  const double cells_across = extent / base;
  edge_ = base * (1.0 + 1e-12 + 32.0 * kEps * (cells_across + 2.0));
  inv_edge_ = 1.0 / edge_;
  slack_ = 32.0 * kEps * (extent * inv_edge_ + 2.0);

  const std::uint64_t capacity = std::bit_ceil(std::max<std::uint64_t>(16, 2 * std::uint64_t(n)));
  table_.resize(capacity);
  for (Slot& s : table_) s.cell = -1;
  mask_ = capacity - 1;
  cells_.clear();
  cells_.reserve(n);  // at most one cell per member: no growth while inserting
  cell_of_.resize(n);

  for (std::int32_t k = 0; k < n; ++k) {
    const Vec3& c = spheres.centers[members[k]];
    const std::int32_t cell = findOrInsert(keyOf(c.x(), c.y(), c.z()));
    cell_of_[k] = cell;
    ++cells_[cell].end;  // count for now
  }
  std::int32_t start = 0;
  for (Cell& cell : cells_) {
    const std::int32_t count = cell.end;
    cell.begin = start;
    cell.end = start;  // write cursor
    start += count;
  }
  items_.resize(n);
  index_.resize(n);
  for (std::int32_t k = 0; k < n; ++k) {
    const std::int32_t m = members[k];
    const std::int32_t pos = cells_[cell_of_[k]].end++;
    const Vec3& c = spheres.centers[m];
    items_[pos] = {c.x(), c.y(), c.z(), spheres.radii[m]};
    index_[pos] = m;
  }
}

void CellGrid::boxAround(double x, double y, double z, double h, CellKey& lo, CellKey& hi) const {
  const double span = h * inv_edge_ * (1.0 + 1e-12) + slack_;
  const double s[3] = {(x - origin_.x()) * inv_edge_, (y - origin_.y()) * inv_edge_,
                       (z - origin_.z()) * inv_edge_};
  lo = {static_cast<std::int64_t>(std::floor(s[0] - span)),
        static_cast<std::int64_t>(std::floor(s[1] - span)),
        static_cast<std::int64_t>(std::floor(s[2] - span))};
  hi = {static_cast<std::int64_t>(std::floor(s[0] + span)),
        static_cast<std::int64_t>(std::floor(s[1] + span)),
        static_cast<std::int64_t>(std::floor(s[2] + span))};
}

}  // namespace polydem::broadphase::detail
