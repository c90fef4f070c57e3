// A sorted cell list: the building block of the NBS and multi-level searches (internal).
//
// Particles are put into cubic cells by their centre, as in Zhao eqs. (37)-(39), but with
// floor() from the lowest centre of the scene instead of Fortran's 1 + int(x + 0.5) (the same
// mapping shifted by half a cell). Only occupied cells are stored: the members are sorted by
// cell in (z, y, x) order (a stable radix sort on the cell's index in the scene's box of cells,
// 11 bits per pass, as many passes as that index needs), and a cell is a run of equal keys. When
// a grid is rebuilt for the same members (the next time step), the sort starts from their last
// order instead and an insertion sort moves the few that changed cells, to the same order. So a
// scene spread over a huge, mostly empty region (millimetre grains at 1e6 m, a far ghost) costs
// memory and time in proportion to the particles, never to the volume, and the members of
// neighbouring cells of a row lie next to each other in memory. Within a grid, neighbour cells
// are found by sweeping (grid_search.cpp); a grid that smaller particles search also gets a table
// from cell key to cell (find()): a plain array over the scene's box of cells when that box has
// at most kDenseFactor cells per occupied cell (large particles packed in a compact region: the
// usual case), else a hash table sized by the occupied cells, never by the volume.
//
// Rounding. Cell coordinates are computed in floating point, so two centres at exactly the reach
// could land two cells apart. The edge is therefore enlarged by a relative slack that bounds the
// rounding of (x - x0) / edge over the whole scene (a few ulps times the number of cells across),
// which makes the neighbour-cell rule exact for every pair withinReach() accepts; query boxes get
// the same slack.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "polydem/broadphase/broad_phase.h"
#include "polydem/broadphase/scene_bounds.h"

namespace polydem::broadphase::detail {

/// The members' centres and radii as the inner loops read them: four parallel arrays in cell
/// order, so that two or four consecutive members load as one vector per coordinate
/// (sphere_tests.h). Each array has three entries of padding past the last member (kPad): a
/// four-lane test may read them, and their outcomes are discarded.
struct Coords {
  const double* x;
  const double* y;
  const double* z;
  const double* r;
};
inline constexpr std::size_t kPad = 3;

/// What a pair needs besides the geometry: its canonical order and whether it counts.
struct Meta {
  Uid uid;
  std::int32_t index;  // local index into the SphereSet
  std::uint8_t active;
};

/// Appends candidate pairs to a vector without a branch per pair: a pair is written
/// unconditionally at the end and kept by advancing the end by the test's outcome (0 or 1). The
/// outcomes are hard to predict (a third hit among neighbours of one size), and a mispredicted
/// branch costs more than the write. The vector's elements past the pairs are scratch: it is
/// resized only to grow (so no element is zeroed twice) and cut to the pairs by finish().
///
/// The searches write in two steps: the tests write the grid positions of each hit (cheap: no
/// uid, index or flag is read per test), and resolve() then turns the positions written since a
/// mark() into local indices in canonical order, dropping pairs without an active member. Only
/// about one test in six hits, so the per-pair work is done six times less often.
class PairWriter {
 public:
  /// Starts `out` afresh (its old pairs are dropped).
  explicit PairWriter(std::vector<CandidatePair>& out) : out_(out) {}
  /// Without finish() (an exception on the way), `out` is left empty.
  ~PairWriter() {
    if (!finished_) out_.clear();
  }
  PairWriter(const PairWriter&) = delete;
  PairWriter& operator=(const PairWriter&) = delete;
  /// Room for `k` more pairs after the ones kept; returns where the next one goes.
  /// Two-lane writers ask for one more than they can keep.
  CandidatePair* room(std::size_t k) {
    if (count_ + k > out_.size()) out_.resize(std::max(count_ + k, 2 * out_.size()));
    return out_.data() + count_;
  }
  /// Keeps the pairs written from room()'s pointer up to `end`.
  void keep(const CandidatePair* end) { count_ = static_cast<std::size_t>(end - out_.data()); }
  /// Where resolve() will start: the number of pairs kept so far.
  std::size_t mark() const { return count_; }
  /// Turns the pairs kept since `from` (positions: i in the grid of `meta_i`, j in that of
  /// `meta_j`) into local indices, lower uid first, and drops those without an active member.
  void resolve(std::size_t from, const Meta* meta_i, const Meta* meta_j);
  /// Cuts `out` to the pairs kept.
  void finish() {
    out_.resize(count_);
    finished_ = true;
  }

 private:
  std::vector<CandidatePair>& out_;
  std::size_t count_ = 0;
  bool finished_ = false;
};

/// Writes the pair (a, b), lower uid first, at `w`, and returns the next place: `w` + 1 if
/// `keep` (1; 0 leaves the write as scratch). No branch: the order is chosen by a mask, not by
/// `?:`, which compilers turn into a branch on the uids, unpredictable where uid order is not
/// space order. Whether an inactive pair is kept is the caller's part (pairCounts()).
inline CandidatePair* writePair(const Meta& a, const Meta& b, std::uint32_t keep,
                                CandidatePair* w) {
  const std::uint32_t b_first = 0u - static_cast<std::uint32_t>(b.uid < a.uid);
  const std::uint32_t flip =
      (static_cast<std::uint32_t>(a.index) ^ static_cast<std::uint32_t>(b.index)) & b_first;
  w->i = static_cast<std::int32_t>(static_cast<std::uint32_t>(a.index) ^ flip);
  w->j = static_cast<std::int32_t>(static_cast<std::uint32_t>(b.index) ^ flip);
  return w + keep;
}

/// 1 if a pair of `a` and `b` counts (one of them active), else 0.
inline std::uint32_t pairCounts(const Meta& a, const Meta& b) {
  return static_cast<std::uint32_t>((a.active | b.active) != 0);
}

inline void PairWriter::resolve(std::size_t from, const Meta* meta_i, const Meta* meta_j) {
  CandidatePair* w = out_.data() + from;
  const CandidatePair* const end = out_.data() + count_;
  // In place: the write at w never passes the pair being read.
  for (const CandidatePair* p = w; p != end; ++p) {
    const Meta& a = meta_i[p->i];
    const Meta& b = meta_j[p->j];
    w = writePair(a, b, pairCounts(a, b), w);
  }
  keep(w);
}

struct CellKey {
  std::int64_t x, y, z;
  friend bool operator==(const CellKey&, const CellKey&) = default;
};

/// floor() to an integer, inline (std::floor is a library call without SSE4.1); |v| < 2^63.
inline std::int64_t floorToInt(double v) {
  const auto t = static_cast<std::int64_t>(v);  // truncates towards zero
  return t - static_cast<std::int64_t>(v < static_cast<double>(t));
}

/// (z, y, x) lexicographic order: the order cells are stored in.
inline bool cellBefore(const CellKey& a, const CellKey& b) {
  if (a.z != b.z) return a.z < b.z;
  if (a.y != b.y) return a.y < b.y;
  return a.x < b.x;
}

/// A dense lookup array may have this many entries per occupied cell.
inline constexpr double kDenseFactor = 8.0;

/// Cells of one edge over the bounds of a whole SphereSet.
class CellGrid {
 public:
  struct Cell {
    CellKey key;
    std::int32_t begin, end;  // range in coords() / meta()
  };

  /// Puts `members` (indices into `spheres`) into cells of edge >= `reach`, the largest distance
  /// at which two members, or a member and a query, can form a pair. `bounds` are those of the
  /// whole set, so that every centre of the set maps with the same arithmetic. With `lookup`,
  /// also builds the table behind find(). Reuses storage.
  void build(const SphereSet& spheres, std::span<const std::int32_t> members, double reach,
             const SceneBounds& bounds, bool lookup);

  double edge() const { return edge_; }
  /// Members in cell order: coordinates (padded, see Coords) and what pairs need.
  Coords coords() const { return {x_.data(), y_.data(), z_.data(), r_.data()}; }
  std::span<const Meta> meta() const { return {meta_.data(), size_}; }
  std::size_t size() const { return size_; }
  std::span<const Cell> cells() const { return cells_; }
  /// Largest and smallest radius among the members (0 for an empty grid).
  double maxRadius() const { return max_radius_; }
  double minRadius() const { return min_radius_; }

  /// The cell with this key, or -1 if it is empty. Needs build(..., lookup = true).
  std::int32_t find(const CellKey& key) const {
    if (dense_) {
      if (key.x < -1 || key.x > nx_ - 2 || key.y < -1 || key.y > ny_ - 2 || key.z < -1 ||
          key.z > nz_ - 2) {
        return -1;
      }
      return table_[static_cast<std::size_t>(packed(key))];
    }
    for (std::uint64_t slot = hash(key) & mask_;; slot = (slot + 1) & mask_) {
      const std::int32_t cell = table_[slot];
      if (cell < 0 || cells_[cell].key == key) return cell;
    }
  }

  /// Whether find() uses the array over the box of cells (else the hash table).
  bool denseLookup() const { return dense_; }

  /// The key of the cell a centre falls in.
  CellKey keyOf(double x, double y, double z) const {
    return {coord(x - origin_.x()), coord(y - origin_.y()), coord(z - origin_.z())};
  }

  /// The keys of all cells that can hold a member within `h` of some point of the box
  /// [lo_point, hi_point], as a box of keys [lo, hi]. Conservative by the rounding slack.
  void keysAround(const Vec3& lo_point, const Vec3& hi_point, double h, CellKey& lo,
                  CellKey& hi) const {
    const double span = h * inv_edge_ * (1.0 + 1e-12) + slack_;
    lo = {floorToInt((lo_point.x() - origin_.x()) * inv_edge_ - span),
          floorToInt((lo_point.y() - origin_.y()) * inv_edge_ - span),
          floorToInt((lo_point.z() - origin_.z()) * inv_edge_ - span)};
    hi = {floorToInt((hi_point.x() - origin_.x()) * inv_edge_ + span),
          floorToInt((hi_point.y() - origin_.y()) * inv_edge_ + span),
          floorToInt((hi_point.z() - origin_.z()) * inv_edge_ + span)};
  }

 private:
  static std::uint64_t hash(const CellKey& k) {
    std::uint64_t h = static_cast<std::uint64_t>(k.x) * 0x9E3779B97F4A7C15ull +
                      static_cast<std::uint64_t>(k.y) * 0xC2B2AE3D27D4EB4Full +
                      static_cast<std::uint64_t>(k.z) * 0x165667B19E3779F9ull;
    h ^= h >> 31;
    h *= 0xD6E8FEB86659FD93ull;
    return h ^ (h >> 32);
  }
  std::int64_t coord(double offset) const { return floorToInt(offset * inv_edge_); }
  /// The cell's index in the padded box of cells, in (z, y, x) order.
  std::int64_t packed(const CellKey& key) const {
    return (key.x + 1) + nx_ * ((key.y + 1) + ny_ * (key.z + 1));
  }
  void sortMembers(const SphereSet& spheres, std::span<const std::int32_t> members);
  void gather(const SphereSet& spheres, std::size_t p, std::int32_t m);
  void sortByRadix(const SphereSet& spheres, std::span<const std::int32_t> members);
  bool sortFromLastOrder(const SphereSet& spheres);
  void cellsFromKeys();
  void sortByComparison(const SphereSet& spheres, std::span<const std::int32_t> members);
  void buildLookup();

  Vec3 origin_ = Vec3::Zero();
  double edge_ = 1.0;
  double inv_edge_ = 1.0;
  double slack_ = 0.0;  // cells
  double max_radius_ = 0.0;
  double min_radius_ = 0.0;
  // The scene's box of cells, padded by one cell on each side, for the packed sort key.
  std::int64_t nx_ = 0, ny_ = 0, nz_ = 0;
  double box_cells_ = 0.0;
  int key_bits_ = 0;      // 0: the box is too large to pack; sort by comparing keys instead
  std::size_t size_ = 0;  // members
  std::vector<double> x_, y_, z_, r_;  // size_ + kPad each
  std::vector<Meta> meta_;             // size_ + kPad
  std::vector<Cell> cells_;
  bool dense_ = false;               // table_ is indexed by packed(key), else by hash slot
  std::vector<std::int32_t> table_;  // -> cell, -1 empty
  std::uint64_t mask_ = 0;
  // Sort scratch.
  std::vector<std::uint64_t> keys_, keys_tmp_;
  std::vector<std::int32_t> order_, order_tmp_;
  std::vector<CellKey> cell_keys_;
  // The members of the last build, sorted by packed keys (last_sorted_): when the next build has
  // the same members, their last order (meta_'s indices) is the starting point of the sort.
  std::vector<std::int32_t> last_members_;
  bool last_sorted_ = false;

 public:
  /// Heap bytes of its arrays and sort scratch (capacities, core/memory.h).
  std::uint64_t heapBytes() const;
};

}  // namespace polydem::broadphase::detail
