#include "polydem/domain/block_forest.h"

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdint>

#include "polydem/core/strings.h"
#include "polydem/domain/domain_error.h"

namespace polydem::domain {

namespace {

constexpr char kAxisName[3] = {'x', 'y', 'z'};

bool finite(const Vec3& v) {
  return std::isfinite(v.x()) && std::isfinite(v.y()) && std::isfinite(v.z());
}

/// Periodic image numbers beyond this many per axis mean a radius absurdly larger than the
/// domain; refusing them keeps a typo from turning one query into billions of hits.
constexpr long kMaxImagesPerAxis = 1024;

}  // namespace

BlockForest::BlockForest(const Aabb& domain, const Index3& counts, const Periodic& periodic)
    : domain_(domain), counts_(counts), periodic_(periodic) {
  if (!finite(domain.lo) || !finite(domain.hi)) {
    throw DomainError("BlockForest: domain box has a non-finite corner");
  }
  std::int64_t total = 1;
  for (int a = 0; a < 3; ++a) {
    if (!(domain.hi[a] > domain.lo[a])) {
      throw DomainError(cat("BlockForest: domain box is empty along ", kAxisName[a], " (lo ",
                            domain.lo[a], ", hi ", domain.hi[a], ")"));
    }
    if (counts[a] < 1) {
      throw DomainError(cat("BlockForest: block count along ", kAxisName[a], " is ", counts[a],
                            "; it must be at least 1"));
    }
    total *= counts[a];
    if (total > INT_MAX) {
      throw DomainError(cat("BlockForest: ", counts[0], " x ", counts[1], " x ", counts[2],
                            " blocks exceed the 2^31-1 block limit"));
    }
  }
  num_blocks_ = static_cast<int>(total);
  length_ = domain.hi - domain.lo;
  for (int a = 0; a < 3; ++a) {
    const int n = counts[a];
    block_size_[a] = length_[a] / n;
    inv_block_size_[a] = n / length_[a];
    auto& e = edges_[a];
    e.resize(n + 1);
    e[0] = domain.lo[a];
    for (int i = 1; i < n; ++i) e[i] = domain.lo[a] + length_[a] * i / n;
    e[n] = domain.hi[a];
    for (int i = 0; i < n; ++i) {
      if (!(e[i] < e[i + 1])) {
        throw DomainError(cat("BlockForest: ", n, " blocks along ", kAxisName[a],
                              " are thinner than the floating-point resolution of the domain"));
      }
    }
  }
  setRankMap(std::vector<int>(num_blocks_, 0), 1);
}

int BlockForest::blockIndex(const Index3& ijk) const {
  for (int a = 0; a < 3; ++a) {
    if (ijk[a] < 0 || ijk[a] >= counts_[a]) return -1;
  }
  return ijk[0] + counts_[0] * (ijk[1] + counts_[1] * ijk[2]);
}

Index3 BlockForest::blockCoords(int b) const {
  const int ix = b % counts_[0];
  const int rest = b / counts_[0];
  return {ix, rest % counts_[1], rest / counts_[1]};
}

Aabb BlockForest::blockBox(int b) const {
  const Index3 c = blockCoords(b);
  return Aabb(Vec3(edges_[0][c[0]], edges_[1][c[1]], edges_[2][c[2]]),
              Vec3(edges_[0][c[0] + 1], edges_[1][c[1] + 1], edges_[2][c[2] + 1]));
}

int BlockForest::neighbourIndex(int b, const Index3& offset) const {
  Index3 c = blockCoords(b);
  for (int a = 0; a < 3; ++a) {
    const int n = counts_[a];
    // in 64 bits: an offset near INT_MAX must not overflow
    std::int64_t v = static_cast<std::int64_t>(c[a]) + offset[a];
    if (v < 0 || v >= n) {
      if (!periodic_[a]) return -1;
      v %= n;
      if (v < 0) v += n;
    }
    c[a] = static_cast<int>(v);
  }
  return blockIndex(c);
}

int BlockForest::axisCell(int axis, double x) const {
  const auto& e = edges_[axis];
  const int n = counts_[axis];
  int i = std::clamp(static_cast<int>((x - e[0]) * inv_block_size_[axis]), 0, n - 1);
  // The estimate can be off by one near a boundary through rounding; the stored edges decide.
  while (i > 0 && x < e[i]) --i;
  while (i < n - 1 && x >= e[i + 1]) ++i;
  return i;
}

int BlockForest::axisCellEstimate(int axis, double x) const {
  const double cell = std::floor((x - edges_[axis][0]) * inv_block_size_[axis]);
  return static_cast<int>(std::clamp(cell, -1.0, static_cast<double>(counts_[axis])));
}

Vec3 BlockForest::wrap(const Vec3& x) const {
  Vec3 y = x;
  for (int a = 0; a < 3; ++a) {
    if (!periodic_[a] || !std::isfinite(x[a])) continue;
    const double lo = domain_.lo[a], hi = domain_.hi[a];
    if (x[a] >= lo && x[a] < hi) continue;
    double t = std::fmod(x[a] - lo, length_[a]);
    if (t < 0) t += length_[a];
    y[a] = lo + t;
    if (!(y[a] >= lo && y[a] < hi)) y[a] = lo;  // rounded onto hi: the same point as lo
  }
  return y;
}

int BlockForest::blockOf(const Vec3& x) const {
  const Vec3 y = wrap(x);
  Index3 c;
  for (int a = 0; a < 3; ++a) {
    // Also rejects NaN. Periodic axes are already inside [lo, hi).
    if (!(y[a] >= domain_.lo[a] && y[a] <= domain_.hi[a])) return -1;
    c[a] = axisCell(a, y[a]);
  }
  return blockIndex(c);
}

std::vector<int> BlockForest::neighbours(int b) const {
  std::vector<int> out;
  out.reserve(26);
  for (int dz = -1; dz <= 1; ++dz) {
    for (int dy = -1; dy <= 1; ++dy) {
      for (int dx = -1; dx <= 1; ++dx) {
        if (dx == 0 && dy == 0 && dz == 0) continue;
        const int nb = neighbourIndex(b, {dx, dy, dz});
        if (nb >= 0 && nb != b) out.push_back(nb);
      }
    }
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

// Visits every (block, image) whose box is within `radius` of center + shift. Candidates are
// pruned per axis by the one-axis distance, which never exceeds the box distance computed by
// Aabb::distance (each of its squared terms is at most the rounded total), so pruning cannot drop
// a hit that the final Aabb::distance test would accept.
template <typename Visit>
void BlockForest::forEachSphereHit(const Vec3& center, double radius, Visit&& visit) const {
  if (!finite(center) || !std::isfinite(radius)) {
    throw DomainError(cat("BlockForest: sphere query with non-finite centre (", center.x(), ", ",
                          center.y(), ", ", center.z(), ") or radius ", radius));
  }
  if (radius < 0) return;
  // Per axis: the range of images to try.
  Index3 image_lo{0, 0, 0}, image_hi{0, 0, 0};
  for (int a = 0; a < 3; ++a) {
    if (!periodic_[a]) continue;
    // image k reaches [lo, hi] iff lo - r <= c + k L <= hi + r; one extra image either side
    // absorbs rounding, the exact test below rejects it.
    const double k_lo = std::ceil((domain_.lo[a] - radius - center[a]) / length_[a]) - 1;
    const double k_hi = std::floor((domain_.hi[a] + radius - center[a]) / length_[a]) + 1;
    if (k_hi - k_lo > kMaxImagesPerAxis) {
      throw DomainError(cat("BlockForest: sphere radius ", radius, " spans more than ",
                            kMaxImagesPerAxis, " periodic images along ", kAxisName[a]));
    }
    image_lo[a] = static_cast<int>(k_lo);
    image_hi[a] = static_cast<int>(k_hi);
  }
  auto axis_range = [&](int a, double p, int& first, int& last) {
    first = std::max(axisCellEstimate(a, p - radius) - 1, 0);
    last = std::min(axisCellEstimate(a, p + radius) + 1, counts_[a] - 1);
  };
  auto axis_reaches = [&](int a, int i, double p) {
    const double d = std::max({edges_[a][i] - p, 0.0, p - edges_[a][i + 1]});
    return std::sqrt(d * d) <= radius;
  };
  Index3 image, cell, first, last;
  Vec3 shift;
  for (image[2] = image_lo[2]; image[2] <= image_hi[2]; ++image[2]) {
    shift[2] = image[2] * length_[2];
    const double pz = center[2] + shift[2];
    axis_range(2, pz, first[2], last[2]);
    for (cell[2] = first[2]; cell[2] <= last[2]; ++cell[2]) {
      if (!axis_reaches(2, cell[2], pz)) continue;
      for (image[1] = image_lo[1]; image[1] <= image_hi[1]; ++image[1]) {
        shift[1] = image[1] * length_[1];
        const double py = center[1] + shift[1];
        axis_range(1, py, first[1], last[1]);
        for (cell[1] = first[1]; cell[1] <= last[1]; ++cell[1]) {
          if (!axis_reaches(1, cell[1], py)) continue;
          for (image[0] = image_lo[0]; image[0] <= image_hi[0]; ++image[0]) {
            shift[0] = image[0] * length_[0];
            const double px = center[0] + shift[0];
            axis_range(0, px, first[0], last[0]);
            for (cell[0] = first[0]; cell[0] <= last[0]; ++cell[0]) {
              if (!axis_reaches(0, cell[0], px)) continue;
              const int b = blockIndex(cell);
              if (blockBox(b).distance(center + shift) <= radius) visit(b, image, shift);
            }
          }
        }
      }
    }
  }
}

// The cells of forEachSphereHit's candidate range that pass its per-axis test, with the same
// arithmetic: every block it hits (without periodic images) lies in their product.
bool BlockForest::sphereWithinRank(const Vec3& center, double radius, int rank) const {
  if (periodic_[0] || periodic_[1] || periodic_[2]) return false;
  if (!finite(center) || !std::isfinite(radius) || radius < 0) return false;
  Index3 first, last;
  for (int a = 0; a < 3; ++a) {
    const double p = center[a];
    first[a] = std::max(axisCellEstimate(a, p - radius) - 1, 0);
    last[a] = std::min(axisCellEstimate(a, p + radius) + 1, counts_[a] - 1);
    auto reaches = [&](int i) {
      const double d = std::max({edges_[a][i] - p, 0.0, p - edges_[a][i + 1]});
      return std::sqrt(d * d) <= radius;
    };
    while (first[a] <= last[a] && !reaches(first[a])) ++first[a];
    while (last[a] >= first[a] && !reaches(last[a])) --last[a];
  }
  Index3 cell;
  for (cell[2] = first[2]; cell[2] <= last[2]; ++cell[2]) {
    for (cell[1] = first[1]; cell[1] <= last[1]; ++cell[1]) {
      for (cell[0] = first[0]; cell[0] <= last[0]; ++cell[0]) {
        if (rank_of_block_[blockIndex(cell)] != rank) return false;
      }
    }
  }
  return true;
}

void BlockForest::blocksIntersectingSphere(const Vec3& center, double radius,
                                           std::vector<BlockHit>& out) const {
  out.clear();
  forEachSphereHit(center, radius, [&](int b, const Index3& image, const Vec3& shift) {
    out.push_back({b, image, shift});
  });
  std::sort(out.begin(), out.end(), [](const BlockHit& p, const BlockHit& q) {
    return p.block != q.block ? p.block < q.block : p.image < q.image;
  });
}

std::vector<BlockHit> BlockForest::blocksIntersectingSphere(const Vec3& center,
                                                            double radius) const {
  std::vector<BlockHit> out;
  blocksIntersectingSphere(center, radius, out);
  return out;
}

void BlockForest::ranksIntersectingSphere(const Vec3& center, double radius,
                                          std::vector<RankHit>& out) const {
  out.clear();
  forEachSphereHit(center, radius, [&](int b, const Index3& image, const Vec3& shift) {
    out.push_back({rank_of_block_[b], image, shift});
  });
  auto key_less = [](const RankHit& p, const RankHit& q) {
    return p.rank != q.rank ? p.rank < q.rank : p.image < q.image;
  };
  auto key_equal = [](const RankHit& p, const RankHit& q) {
    return p.rank == q.rank && p.image == q.image;
  };
  std::sort(out.begin(), out.end(), key_less);
  out.erase(std::unique(out.begin(), out.end(), key_equal), out.end());
}

std::vector<RankHit> BlockForest::ranksIntersectingSphere(const Vec3& center, double radius) const {
  std::vector<RankHit> out;
  ranksIntersectingSphere(center, radius, out);
  return out;
}

void BlockForest::setRankMap(std::vector<int> block_to_rank, int ranks) {
  if (static_cast<int>(block_to_rank.size()) != num_blocks_) {
    throw DomainError(cat("BlockForest::setRankMap: map has ", block_to_rank.size(),
                          " entries for ", num_blocks_, " blocks"));
  }
  if (ranks < 0) throw DomainError(cat("BlockForest::setRankMap: ", ranks, " ranks"));
  if (ranks == 0) ranks = *std::max_element(block_to_rank.begin(), block_to_rank.end()) + 1;
  for (int b = 0; b < num_blocks_; ++b) {
    if (block_to_rank[b] < 0 || block_to_rank[b] >= ranks) {
      throw DomainError(cat("BlockForest::setRankMap: block ", b, " is given to rank ",
                            block_to_rank[b], ", outside [0, ", ranks, ")"));
    }
  }
  rank_of_block_ = std::move(block_to_rank);
  num_ranks_ = ranks;
  // Counting sort by rank keeps each rank's blocks in ascending order.
  rank_offsets_.assign(ranks + 1, 0);
  for (int r : rank_of_block_) ++rank_offsets_[r + 1];
  for (int r = 0; r < ranks; ++r) rank_offsets_[r + 1] += rank_offsets_[r];
  rank_blocks_.resize(num_blocks_);
  std::vector<int> fill(rank_offsets_.begin(), rank_offsets_.end() - 1);
  for (int b = 0; b < num_blocks_; ++b) rank_blocks_[fill[rank_of_block_[b]]++] = b;
}

std::span<const int> BlockForest::blocksOfRank(int r) const {
  if (r < 0 || r >= num_ranks_) return {};
  return std::span<const int>(rank_blocks_)
      .subspan(rank_offsets_[r], rank_offsets_[r + 1] - rank_offsets_[r]);
}

int BlockForest::ownerOf(const Vec3& x) const {
  const int b = blockOf(x);
  return b < 0 ? -1 : rank_of_block_[b];
}

std::vector<int> BlockForest::neighbourRanks(int r) const {
  std::vector<int> out;
  for (int b : blocksOfRank(r)) {
    for (int nb : neighbours(b)) {
      if (rank_of_block_[nb] != r) out.push_back(rank_of_block_[nb]);
    }
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

std::vector<int> BlockForest::ranksWithin(int r, double distance) const {
  // A block k blocks away along an axis is at least (k - 1) block sizes away along it; the
  // factor 1 + 1e-9 covers edges that differ from the nominal size by rounding.
  Index3 reach{};
  for (int a = 0; a < 3; ++a) {
    const double cells = std::floor(std::max(distance, 0.0) * inv_block_size_[a] * (1.0 + 1e-9));
    reach[a] = static_cast<int>(std::min<double>(cells + 1.0, counts_[a]));
  }
  std::vector<int> out;
  for (int b : blocksOfRank(r)) {
    for (int k = -reach[2]; k <= reach[2]; ++k) {
      for (int j = -reach[1]; j <= reach[1]; ++j) {
        for (int i = -reach[0]; i <= reach[0]; ++i) {
          const int nb = neighbourIndex(b, {i, j, k});
          if (nb >= 0 && rank_of_block_[nb] != r) out.push_back(rank_of_block_[nb]);
        }
      }
    }
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

Index3 chooseBlockCounts(const Aabb& domain, int ranks, int blocks_per_rank_hint,
                         double min_block_edge) {
  if (ranks < 1) throw DomainError(cat("chooseBlockCounts: ", ranks, " ranks"));
  if (blocks_per_rank_hint < 1) {
    throw DomainError(cat("chooseBlockCounts: blocks_per_rank_hint is ", blocks_per_rank_hint,
                          "; it must be at least 1"));
  }
  if (!(min_block_edge >= 0) || !std::isfinite(min_block_edge)) {
    throw DomainError(cat("chooseBlockCounts: min_block_edge is ", min_block_edge));
  }
  const Vec3 length = domain.extent();
  for (int a = 0; a < 3; ++a) {
    if (!(length[a] > 0) || !std::isfinite(length[a])) {
      throw DomainError(
          cat("chooseBlockCounts: domain box is empty or non-finite along ", kAxisName[a]));
    }
  }
  const std::int64_t target = static_cast<std::int64_t>(ranks) * blocks_per_rank_hint;
  if (target > INT_MAX) {
    throw DomainError(cat("chooseBlockCounts: ", ranks, " ranks x ", blocks_per_rank_hint,
                          " blocks per rank exceed the 2^31-1 block limit"));
  }
  constexpr double kTie = 1e-12;  // relative: equal edges stay equal at any length scale
  Index3 n{1, 1, 1};
  std::int64_t total = 1;
  while (total < target) {
    int best = -1;
    double best_edge = 0;
    for (int a = 0; a < 3; ++a) {
      const double edge = length[a] / n[a];
      if (length[a] / (n[a] + 1) < min_block_edge) continue;
      if (best < 0 || edge > best_edge * (1 + kTie)) {
        best = a;
        best_edge = edge;
      }
    }
    if (best < 0) break;
    total = total / n[best] * (n[best] + 1);
    ++n[best];
  }
  if (total < ranks) {
    throw DomainError(cat("chooseBlockCounts: blocks of edge >= ", min_block_edge, " give only ",
                          total, " blocks (", n[0], " x ", n[1], " x ", n[2], ") for ", ranks,
                          " ranks"));
  }
  return n;
}

}  // namespace polydem::domain
