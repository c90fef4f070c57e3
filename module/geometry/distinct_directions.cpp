#include "polydem/geometry/distinct_directions.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>

namespace polydem::geometry {

namespace {

// Below this many directions the pairwise comparison is cheaper than the grid (and allocates
// nothing): every shape of a scene but the finely faceted ones.
constexpr std::size_t kPairwiseUpTo = 64;

bool parallel(const Vec3& a, const Vec3& b, double sin_angle) {
  return a.cross(b).norm() <= sin_angle;
}

std::vector<int> pairwise(std::span<const Vec3> directions, double sin_angle) {
  std::vector<int> kept;
  for (int i = 0; i < static_cast<int>(directions.size()); ++i) {
    const bool found = std::any_of(kept.begin(), kept.end(), [&](int k) {
      return parallel(directions[k], directions[i], sin_angle);
    });
    if (!found) kept.push_back(i);
  }
  return kept;
}

using Cell = std::array<std::int64_t, 3>;

std::uint64_t hashOf(const Cell& c) {
  std::uint64_t h = 0;
  for (const std::int64_t x : c) h = (h ^ static_cast<std::uint64_t>(x)) * 0x9e3779b97f4a7c15ULL;
  return h ^ (h >> 29);
}

// Kept directions by grid cell, each under both signs (a direction parallel to d up to sign is
// near d or near -d). Unit vectors parallel within sin_angle are within a chord of about
// sin_angle of each other (or of each other's opposite); `reach` (twice that) covers it with
// room for rounding, and cells of twice `reach` see each neighbourhood in one to eight cells.
// An open-addressing table of cells, each heading a list of entries: no allocation per entry.
class DirectionGrid {
 public:
  DirectionGrid(double sin_angle, std::size_t capacity)
      : reach_(2.0 * sin_angle), size_(2.0 * reach_) {
    std::size_t slots = 16;
    while (slots < 4 * capacity) slots *= 2;  // two entries per direction, load below one half
    slots_.assign(slots, Slot{});
    next_.reserve(2 * capacity);
    index_.reserve(2 * capacity);
  }

  void add(const Vec3& d, int index) {
    insert(cellOf(d), index);
    insert(cellOf(-d), index);
  }

  // Whether f(index) holds for a kept direction in a cell within `reach` of d in each
  // coordinate (every kept direction that near is in one).
  template <typename F>
  bool anyNear(const Vec3& d, F f) const {
    Cell lo, hi;
    for (int k = 0; k < 3; ++k) {
      lo[k] = coordinate(d[k] - reach_);
      hi[k] = coordinate(d[k] + reach_);
    }
    Cell c;
    for (c[0] = lo[0]; c[0] <= hi[0]; ++c[0]) {
      for (c[1] = lo[1]; c[1] <= hi[1]; ++c[1]) {
        for (c[2] = lo[2]; c[2] <= hi[2]; ++c[2]) {
          const Slot& slot = slots_[find(c)];
          for (int e = slot.head; e >= 0; e = next_[e]) {
            if (f(index_[e])) return true;
          }
        }
      }
    }
    return false;
  }

 private:
  struct Slot {
    Cell cell{};
    int head = -1;  // first entry of the cell's list; -1: an empty slot
  };

  std::int64_t coordinate(double x) const {
    return static_cast<std::int64_t>(std::floor(x / size_));
  }
  Cell cellOf(const Vec3& d) const {
    return {coordinate(d[0]), coordinate(d[1]), coordinate(d[2])};
  }
  // The slot holding `c`, or the empty one where it would go (linear probing).
  std::size_t find(const Cell& c) const {
    const std::size_t mask = slots_.size() - 1;
    std::size_t i = hashOf(c) & mask;
    while (slots_[i].head >= 0 && slots_[i].cell != c) i = (i + 1) & mask;
    return i;
  }
  void insert(const Cell& c, int index) {
    Slot& slot = slots_[find(c)];
    slot.cell = c;
    next_.push_back(slot.head);
    index_.push_back(index);
    slot.head = static_cast<int>(index_.size()) - 1;
  }

  double reach_, size_;
  std::vector<Slot> slots_;
  std::vector<int> next_;   // per entry: the next entry of its cell, or -1
  std::vector<int> index_;  // per entry: the direction's index
};

}  // namespace

std::vector<int> distinctDirections(std::span<const Vec3> directions, double sin_angle) {
  if (directions.size() <= kPairwiseUpTo) return pairwise(directions, sin_angle);
  // Whether a direction is kept depends only on which kept ones are parallel to it, and every
  // such one is in the cells searched: the same set as pairwise(), whatever the grid's order.
  DirectionGrid grid(sin_angle, directions.size());
  std::vector<int> kept;
  for (int i = 0; i < static_cast<int>(directions.size()); ++i) {
    const Vec3& d = directions[i];
    const bool found =
        grid.anyNear(d, [&](int k) { return parallel(directions[k], d, sin_angle); });
    if (found) continue;
    kept.push_back(i);
    grid.add(d, i);
  }
  return kept;
}

}  // namespace polydem::geometry
