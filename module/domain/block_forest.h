// The block forest: the domain box cut into nx*ny*nz equal blocks, and the map that gives every
// block to one MPI rank (waLBerla's blockforest, reduced to a uniform grid of blocks).
//
// Every rank holds the whole forest and the whole block->rank map. A rank owns the particles whose
// centroid lies in its blocks (ownerOf) and receives ghost copies of the particles whose
// interaction sphere reaches one of its blocks (ranksIntersectingSphere). See docs/domain.md.
#pragma once

#include <array>
#include <span>
#include <vector>

#include "polydem/core/types.h"
#include "polydem/domain/aabb.h"

namespace polydem::domain {

/// Integer triple (block coordinates, block counts, periodic image numbers), x first.
using Index3 = std::array<int, 3>;
/// Periodic flag per axis, x first.
using Periodic = std::array<bool, 3>;

/// One block reached by a sphere, possibly through a periodic boundary: the sphere centred at
/// `center + shift` reaches the block's box. `image` counts domain lengths per axis and is
/// nonzero only along periodic axes; shift[a] == image[a] * (domain.hi[a] - domain.lo[a]).
struct BlockHit {
  int block = -1;
  Index3 image{0, 0, 0};
  Vec3 shift = Vec3::Zero();
};

/// One rank reached by a sphere: the rank owns at least one block hit with this image.
struct RankHit {
  int rank = -1;
  Index3 image{0, 0, 0};
  Vec3 shift = Vec3::Zero();
};

class BlockForest {
 public:
  /// Cuts `domain` into counts[0]*counts[1]*counts[2] blocks of equal size. Every block starts on
  /// rank 0 (a one-rank map) until setRankMap is called. Throws DomainError for an empty or
  /// non-finite domain, a count below 1, more than 2^31-1 blocks, or blocks too thin for the
  /// floating-point resolution of the domain coordinates.
  BlockForest(const Aabb& domain, const Index3& counts,
              const Periodic& periodic = {false, false, false});

  const Aabb& domain() const { return domain_; }
  const Index3& counts() const { return counts_; }
  int numBlocks() const { return num_blocks_; }
  const Periodic& periodic() const { return periodic_; }
  bool periodic(int axis) const { return periodic_[axis]; }
  /// Nominal block edge lengths (domain extent / counts).
  Vec3 blockSize() const { return block_size_; }
  /// The counts[axis]+1 block boundary coordinates along `axis`: edges[0] == domain.lo,
  /// edges[n] == domain.hi, strictly increasing. Block i spans [edges[i], edges[i+1]].
  std::span<const double> blockEdges(int axis) const { return edges_[axis]; }

  // --- indexing: b = ix + nx * (iy + ny * iz) ---------------------------------------------------

  /// Block index of block coordinates, or -1 if a coordinate is out of range (no wrapping).
  int blockIndex(const Index3& ijk) const;
  /// Block coordinates of block `b` (0 <= b < numBlocks()).
  Index3 blockCoords(int b) const;
  /// The closed box of block `b`; neighbouring blocks share their faces exactly (same doubles).
  Aabb blockBox(int b) const;
  /// The block at `b + offset` (offsets of any size), wrapped along periodic axes; -1 if it lies
  /// outside along a non-periodic axis. May return `b` itself (periodic axis with 1 block).
  int neighbourIndex(int b, const Index3& offset) const;

  /// The translation of periodic image `image`: image[a] * (hi[a] - lo[a]) along every axis, the
  /// same bits as the shifts of the sphere queries.
  Vec3 imageShift(const Index3& image) const {
    return Vec3(image[0] * length_[0], image[1] * length_[1], image[2] * length_[2]);
  }

  // --- points -----------------------------------------------------------------------------------

  /// The block that owns point `x`. Half-open rule: along each axis block i owns
  /// [edges[i], edges[i+1]), so a point on a shared face belongs to the upper block; along a
  /// non-periodic axis the last block also owns the upper domain face x == hi. Along a periodic
  /// axis `x` is wrapped first (wrap). Returns -1 outside the domain along a non-periodic axis or
  /// for a non-finite coordinate.
  int blockOf(const Vec3& x) const;
  /// `x` mapped into [lo, hi) along every periodic axis (other axes unchanged). Points already in
  /// [lo, hi) are returned bit for bit; a wrapped coordinate that rounds to hi becomes lo.
  Vec3 wrap(const Vec3& x) const;

  /// Face, edge and corner neighbours of block `b` (up to 26), wrapped along periodic axes, each
  /// once, never `b` itself, sorted by block index. Along a periodic axis with 2 blocks the other
  /// block is a neighbour on both sides but listed once; with 1 block the axis adds no neighbour.
  std::vector<int> neighbours(int b) const;

  /// Every block whose box lies within distance `radius` (closed: <=) of `center`, with every
  /// periodic image: hit (b, shift) means blockBox(b).distance(center + shift) <= radius. The
  /// block holding `center` is included with a zero shift. Along a periodic axis the same block
  /// can be hit through several images when the radius is comparable to the domain length.
  /// Sorted by block, then image. Negative radius: no hits; non-finite input: DomainError.
  std::vector<BlockHit> blocksIntersectingSphere(const Vec3& center, double radius) const;
  /// Same, into a caller-owned buffer (cleared first) so that a ghost pass does not allocate.
  void blocksIntersectingSphere(const Vec3& center, double radius,
                                std::vector<BlockHit>& out) const;

  /// True when the sphere can reach no block of another rank than `rank` and no periodic image:
  /// every block that passes the sphere query's per-axis test belongs to `rank`, and no axis is
  /// periodic. A cheap superset test (false when unsure): ranksIntersectingSphere would then
  /// return (rank, zero image) alone, so a particle whose ghost sphere stays inside its owner's
  /// blocks needs no query. Non-finite input: false.
  bool sphereWithinRank(const Vec3& center, double radius, int rank) const;

  /// The distinct (rank, image) pairs over blocksIntersectingSphere, sorted by rank then image.
  /// For ghosts: a particle goes to every hit except (its owner, zero image); a hit on the owner
  /// with a nonzero image is a real periodic self-image.
  std::vector<RankHit> ranksIntersectingSphere(const Vec3& center, double radius) const;
  void ranksIntersectingSphere(const Vec3& center, double radius, std::vector<RankHit>& out) const;

  // --- rank map ---------------------------------------------------------------------------------

  /// Installs a block->rank map: one entry per block, each in [0, ranks). `ranks` = 0 takes the
  /// largest entry + 1. Ranks without blocks are allowed here (partitioners avoid them). Throws
  /// DomainError for a wrong size or an entry out of range.
  void setRankMap(std::vector<int> block_to_rank, int ranks = 0);
  int numRanks() const { return num_ranks_; }
  int rankOfBlock(int b) const { return rank_of_block_[b]; }
  const std::vector<int>& rankMap() const { return rank_of_block_; }
  /// Blocks of rank `r`, sorted by block index (empty for a rank without blocks).
  std::span<const int> blocksOfRank(int r) const;
  /// The rank owning point `x` (rankOfBlock(blockOf(x))), or -1 outside the domain.
  int ownerOf(const Vec3& x) const;
  /// Ranks other than `r` that own a neighbour (neighbours()) of one of r's blocks, sorted. These
  /// are all ghost partners of `r` as long as the interaction range is at most the block size.
  std::vector<int> neighbourRanks(int r) const;
  /// Ranks other than `r` owning a block whose box may lie within `distance` of one of r's blocks
  /// (across periodic faces too), sorted: every block up to floor(distance / block size) + 1
  /// blocks away along each axis, a superset of the exact answer. Symmetric: s is in
  /// ranksWithin(r, d) exactly when r is in ranksWithin(s, d), because block offsets are.
  std::vector<int> ranksWithin(int r, double distance) const;

 private:
  /// Block coordinate along `axis` of a coordinate already inside [edges[0], edges[n]].
  int axisCell(int axis, double x) const;
  /// floor((x - lo) / block size), clamped to [-1, n]; an estimate, for candidate ranges only.
  int axisCellEstimate(int axis, double x) const;
  template <typename Visit>
  void forEachSphereHit(const Vec3& center, double radius, Visit&& visit) const;

  Aabb domain_;
  Index3 counts_;
  Periodic periodic_;
  int num_blocks_ = 0;
  Vec3 length_;
  Vec3 block_size_;
  Vec3 inv_block_size_;
  std::array<std::vector<double>, 3> edges_;

  std::vector<int> rank_of_block_;
  int num_ranks_ = 1;
  std::vector<int> rank_offsets_;  // blocks of rank r: rank_blocks_[rank_offsets_[r] .. [r+1])
  std::vector<int> rank_blocks_;
};

/// Block counts for `ranks` ranks. Rule: start from one block and repeatedly split the axis whose
/// blocks are currently longest (x before y before z on ties within 1e-12) into one more block,
/// until there are at least ranks * blocks_per_rank_hint blocks. Blocks stay as close to cubes as
/// the domain allows, there are never fewer than `ranks` blocks, and several per rank leave METIS
/// room to balance non-uniform loads. A split that would make a block edge shorter than
/// `min_block_edge` (e.g. the largest interaction range, 0 = no limit) is not made; if that stops
/// the splitting below `ranks` blocks, DomainError. The counts depend only on the domain's shape
/// (scale-free).
Index3 chooseBlockCounts(const Aabb& domain, int ranks, int blocks_per_rank_hint = 8,
                         double min_block_edge = 0.0);

}  // namespace polydem::domain
