#include "polydem/broadphase/cell_grid.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <limits>

#include "polydem/core/memory.h"

namespace polydem::broadphase::detail {

namespace {

constexpr double kEps = std::numeric_limits<double>::epsilon();
constexpr int kDigitBits = 11;
constexpr std::size_t kBuckets = std::size_t{1} << kDigitBits;

// Stable LSD radix sort of `keys` (only their low `bits` bits are used) carrying `values`.
void radixSort(std::vector<std::uint64_t>& keys, std::vector<std::int32_t>& values,
               std::vector<std::uint64_t>& keys_tmp, std::vector<std::int32_t>& values_tmp,
               int bits) {
  const std::size_t n = keys.size();
  keys_tmp.resize(n);
  values_tmp.resize(n);
  std::array<std::uint32_t, kBuckets> count;
  for (int shift = 0; shift < bits; shift += kDigitBits) {
    count.fill(0);
    for (std::size_t k = 0; k < n; ++k) ++count[(keys[k] >> shift) & (kBuckets - 1)];
    std::uint32_t start = 0;
    for (auto& c : count) {
      const std::uint32_t here = c;
      c = start;
      start += here;
    }
    for (std::size_t k = 0; k < n; ++k) {
      const std::uint32_t pos = count[(keys[k] >> shift) & (kBuckets - 1)]++;
      keys_tmp[pos] = keys[k];
      values_tmp[pos] = values[k];
    }
    keys.swap(keys_tmp);
    values.swap(values_tmp);
  }
}

constexpr std::size_t kGatherAhead = 16;

void prefetchMember(const SphereSet& spheres, std::int32_t m) {
  __builtin_prefetch(&spheres.centers[m]);
  __builtin_prefetch(&spheres.radii[m]);
  __builtin_prefetch(&spheres.uids[m]);
  __builtin_prefetch(&spheres.active[m]);
}

}  // namespace

void CellGrid::build(const SphereSet& spheres, std::span<const std::int32_t> members, double reach,
                     const SceneBounds& bounds, bool lookup) {
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

  // The scene's box of cells with one empty cell of padding on each side: a cell's neighbours
  // then have distinct packed keys, and the key of every centre of the scene fits.
  const CellKey top = keyOf(bounds.hi.x(), bounds.hi.y(), bounds.hi.z());
  nx_ = top.x + 3;
  ny_ = top.y + 3;
  nz_ = top.z + 3;
  box_cells_ = double(nx_) * double(ny_) * double(nz_);
  key_bits_ = box_cells_ < 0x1.0p62 ? std::bit_width(static_cast<std::uint64_t>(box_cells_)) : 0;

  // The largest and smallest radius are taken in gather(), which reads every member's radius
  // anyway: one pass less over the SphereSet.
  max_radius_ = 0.0;
  min_radius_ = std::numeric_limits<double>::infinity();
  sortMembers(spheres, members);
  if (members.empty()) min_radius_ = 0.0;
  if (lookup) buildLookup();
}

void CellGrid::buildLookup() {
  dense_ = key_bits_ > 0 &&
           box_cells_ <= kDenseFactor * std::max<double>(64.0, static_cast<double>(cells_.size()));
  if (dense_) {
    table_.assign(static_cast<std::size_t>(box_cells_), -1);
    for (std::size_t c = 0; c < cells_.size(); ++c) {
      table_[static_cast<std::size_t>(packed(cells_[c].key))] = static_cast<std::int32_t>(c);
    }
    return;
  }
  const std::uint64_t capacity =
      std::bit_ceil(std::max<std::uint64_t>(16, 2 * static_cast<std::uint64_t>(cells_.size())));
  table_.assign(capacity, -1);
  mask_ = capacity - 1;
  for (std::size_t c = 0; c < cells_.size(); ++c) {
    std::uint64_t slot = hash(cells_[c].key) & mask_;
    while (table_[slot] >= 0) slot = (slot + 1) & mask_;
    table_[slot] = static_cast<std::int32_t>(c);
  }
}

void CellGrid::sortMembers(const SphereSet& spheres, std::span<const std::int32_t> members) {
  const std::size_t n = members.size();
  const bool same_members = last_sorted_ && n == size_ &&
                            std::equal(members.begin(), members.end(), last_members_.begin());
  size_ = n;
  for (auto* coord : {&x_, &y_, &z_, &r_}) {
    coord->resize(n + kPad);
    std::fill(coord->begin() + static_cast<std::ptrdiff_t>(n), coord->end(), 0.0);
  }
  if (!same_members) meta_.resize(n + kPad);  // else meta_ holds the last order, read below
  std::fill(meta_.begin() + static_cast<std::ptrdiff_t>(n), meta_.end(), Meta{0, 0, 0});
  cells_.clear();
  cells_.reserve(n);  // at most one cell per member: no growth below
  last_sorted_ = false;
  if (key_bits_ > 0) {
    if (!(same_members && sortFromLastOrder(spheres))) sortByRadix(spheres, members);
    cellsFromKeys();
    last_members_.assign(members.begin(), members.end());
    last_sorted_ = true;
    return;
  }
  sortByComparison(spheres, members);
}

void CellGrid::gather(const SphereSet& spheres, std::size_t p, std::int32_t m) {
  const Vec3& c = spheres.centers[m];
  x_[p] = c.x();
  y_[p] = c.y();
  z_[p] = c.z();
  const double r = spheres.radii[m];
  r_[p] = r;
  max_radius_ = std::max(max_radius_, r);
  min_radius_ = std::min(min_radius_, r);
  meta_[p] = {spheres.uids[m], m, spheres.active[m]};
}

void CellGrid::sortByRadix(const SphereSet& spheres, std::span<const std::int32_t> members) {
  const std::size_t n = members.size();
  order_.assign(members.begin(), members.end());  // sphere indices, sorted below
  // The cell's index in the padded box of cells: (z, y, x) order, one integer.
  keys_.resize(n);
  for (std::size_t k = 0; k < n; ++k) {
    const Vec3& c = spheres.centers[order_[k]];
    keys_[k] = static_cast<std::uint64_t>(packed(keyOf(c.x(), c.y(), c.z())));
  }
  radixSort(keys_, order_, keys_tmp_, order_tmp_, key_bits_);
  for (std::size_t p = 0; p < n; ++p) gather(spheres, p, order_[p]);
}

bool CellGrid::sortFromLastOrder(const SphereSet& spheres) {
  // Members in the last call's cell order (meta_'s indices), with their new keys. Particles
  // move a fraction of a cell per step, so this order is almost the new one: only members that
  // crossed a cell face are out of place, by a few places.
  const std::size_t n = size_;
  keys_.resize(n);
  for (std::size_t p = 0; p < n; ++p) {
    // Cell order is random order for the SphereSet's arrays: past the L2 cache each gather
    // waits on up to four misses unless they were asked for this far ahead.
    if (p + kGatherAhead < n) prefetchMember(spheres, meta_[p + kGatherAhead].index);
    gather(spheres, p, meta_[p].index);
    const Vec3& c = spheres.centers[meta_[p].index];
    keys_[p] = static_cast<std::uint64_t>(packed(keyOf(c.x(), c.y(), c.z())));
  }
  // Insertion sort by (key, index): the order the stable radix sort of the members (ascending
  // indices) gives, so the result does not depend on the history. Gives up, for the radix
  // sort, once it has moved more than a few places per member (a scene rebuilt or shuffled).
  auto before = [&](std::uint64_t key, std::int32_t index, std::size_t q) {
    return key < keys_[q] || (key == keys_[q] && index < meta_[q].index);
  };
  std::size_t moves = 0;
  const std::size_t max_moves = 4 * n + 64;
  for (std::size_t p = 1; p < n; ++p) {
    if (!before(keys_[p], meta_[p].index, p - 1)) continue;
    const std::uint64_t key = keys_[p];
    const double x = x_[p], y = y_[p], z = z_[p], r = r_[p];
    const Meta meta = meta_[p];
    std::size_t q = p;
    for (; q > 0 && before(key, meta.index, q - 1); --q) {
      if (++moves > max_moves) return false;
      keys_[q] = keys_[q - 1];
      x_[q] = x_[q - 1];
      y_[q] = y_[q - 1];
      z_[q] = z_[q - 1];
      r_[q] = r_[q - 1];
      meta_[q] = meta_[q - 1];
    }
    keys_[q] = key;
    x_[q] = x;
    y_[q] = y;
    z_[q] = z;
    r_[q] = r;
    meta_[q] = meta;
  }
  return true;
}

void CellGrid::cellsFromKeys() {
  CellKey key{0, 0, 0};
  for (std::size_t p = 0; p < size_; ++p) {
    if (p == 0 || keys_[p] != keys_[p - 1]) {  // a new cell: decode its key
      const auto linear = static_cast<std::int64_t>(keys_[p]);
      key = {linear % nx_ - 1, (linear / nx_) % ny_ - 1, linear / (nx_ * ny_) - 1};
      cells_.push_back({key, static_cast<std::int32_t>(p), static_cast<std::int32_t>(p + 1)});
    } else {
      cells_.back().end = static_cast<std::int32_t>(p + 1);
    }
  }
}

void CellGrid::sortByComparison(const SphereSet& spheres, std::span<const std::int32_t> members) {
  // A box of more than 2^62 cells (a scene spanning 1e18 cell sizes): compare keys instead.
  const std::size_t n = members.size();
  cell_keys_.resize(n);
  for (std::size_t k = 0; k < n; ++k) {
    const Vec3& c = spheres.centers[members[k]];
    cell_keys_[k] = keyOf(c.x(), c.y(), c.z());
  }
  order_tmp_.resize(n);
  for (std::size_t k = 0; k < n; ++k) order_tmp_[k] = static_cast<std::int32_t>(k);
  std::sort(order_tmp_.begin(), order_tmp_.end(), [&](std::int32_t a, std::int32_t b) {
    const CellKey& ka = cell_keys_[a];
    const CellKey& kb = cell_keys_[b];
    return cellBefore(ka, kb) || (ka == kb && a < b);
  });
  for (std::size_t p = 0; p < n; ++p) {
    gather(spheres, p, members[order_tmp_[p]]);
    const CellKey& key = cell_keys_[order_tmp_[p]];
    if (p == 0 || !(cells_.back().key == key)) {
      cells_.push_back({key, static_cast<std::int32_t>(p), static_cast<std::int32_t>(p + 1)});
    } else {
      cells_.back().end = static_cast<std::int32_t>(p + 1);
    }
  }
}

std::uint64_t CellGrid::heapBytes() const {
  return capacityBytes(x_) + capacityBytes(y_) + capacityBytes(z_) + capacityBytes(r_) +
         capacityBytes(meta_) + capacityBytes(cells_) + capacityBytes(table_) +
         capacityBytes(keys_) + capacityBytes(keys_tmp_) + capacityBytes(order_) +
         capacityBytes(order_tmp_) + capacityBytes(cell_keys_) + capacityBytes(last_members_);
}

}  // namespace polydem::broadphase::detail
