// A hashed cell list: the building block of the NBS and multi-level searches (internal).
//
// Particles are put into cubic cells by their centre, as in Zhao eqs. (37)-(39), but with
// floor() from the lowest centre instead of Fortran's 1 + int(x + 0.5) (the same mapping shifted
// by half a cell). Only occupied cells exist: cell coordinates are 64-bit integers looked up in
// an open-addressing hash table, so a scene spread over a huge, mostly empty region (particles at
// 1e6 m next to millimetre grains, a far ghost) costs memory and time in proportion to the
// particles, never to the volume. Particles are counting-sorted by cell, so that each cell's
// members lie contiguously in items() (the inner loops stream through them). Building and one
// lookup are O(1) per particle (expected), which is what keeps NBS linear for dense packs; the
// price over a dense array of cells is one hash probe per neighbour-cell visit.
//
// Rounding. Cell coordinates are computed in floating point, so two centres at exactly the reach
// could land two cells apart. The edge is therefore enlarged by a relative slack that bounds the
// rounding of (x - x0) / edge over the whole scene (a few ulps times the number of cells across),
// which makes the neighbour-cell rule exact for every pair withinReach() accepts.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "broadphase/broad_phase.h"
#include "broadphase/scene_bounds.h"

namespace polydem::broadphase::detail {

/// A particle as the inner loops read it: centre and radius, 32 bytes.
struct Item {
  double x, y, z, r;
};

struct CellKey {
  std::int64_t x, y, z;
  friend bool operator==(const CellKey&, const CellKey&) = default;
};

/// Cells of one edge over a subset of a SphereSet.
class CellGrid {
 public:
  struct Cell {
    CellKey key;
    std::int32_t begin, end;  // range in items() / index()
  };

  /// Puts `members` (indices into `spheres`) into cells of edge >= `reach`, the largest distance
  /// at which two members, or a member and a query, can form a pair. `bounds` are those of the
  /// whole set, so that every centre of the set maps with the same arithmetic. Reuses storage.
  void build(const SphereSet& spheres, std::span<const std::int32_t> members, double reach,
             const SceneBounds& bounds);

  double edge() const { return edge_; }
  std::span<const Item> items() const { return items_; }
  std::span<const std::int32_t> index() const { return index_; }
  std::span<const Cell> cells() const { return cells_; }
  /// Largest radius among the members (0 for an empty grid).
  double maxRadius() const { return max_radius_; }

  /// The cell holding the key, or -1 if it is empty.
  std::int32_t find(const CellKey& key) const {
    for (std::uint64_t slot = hash(key) & mask_;; slot = (slot + 1) & mask_) {
      const Slot& s = table_[slot];
      if (s.cell < 0) return -1;
      if (s.key == key) return s.cell;
    }
  }

  /// The key of the cell a centre falls in.
  CellKey keyOf(double x, double y, double z) const {
    return {coord(x - origin_.x()), coord(y - origin_.y()), coord(z - origin_.z())};
  }

  /// The keys of all cells that can hold a member within `h` of the point (x, y, z), as a box
  /// [lo, hi]. Conservative by the same rounding slack as the edge.
  void boxAround(double x, double y, double z, double h, CellKey& lo, CellKey& hi) const;

 private:
  struct Slot {
    CellKey key;
    std::int32_t cell;
  };
  static std::uint64_t hash(const CellKey& k) {
    std::uint64_t h = static_cast<std::uint64_t>(k.x) * 0x9E3779B97F4A7C15ull +
                      static_cast<std::uint64_t>(k.y) * 0xC2B2AE3D27D4EB4Full +
                      static_cast<std::uint64_t>(k.z) * 0x165667B19E3779F9ull;
    h ^= h >> 31;
    h *= 0xD6E8FEB86659FD93ull;
    return h ^ (h >> 32);
  }
  std::int64_t coord(double offset) const;
  std::int32_t findOrInsert(const CellKey& key);

  Vec3 origin_ = Vec3::Zero();
  double edge_ = 1.0;
  double inv_edge_ = 1.0;
  double slack_ = 0.0;  // cells
  double max_radius_ = 0.0;
  std::uint64_t mask_ = 0;
  std::vector<Slot> table_;
  std::vector<Cell> cells_;
  std::vector<std::int32_t> cell_of_;  // per member, during build
  std::vector<Item> items_;
  std::vector<std::int32_t> index_;
};

}  // namespace polydem::broadphase::detail
