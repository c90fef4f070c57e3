#include "polydem/domain/block_fit.h"

#include <algorithm>
#include <array>
#include <climits>
#include <cmath>
#include <unordered_set>

#include "polydem/core/strings.h"
#include "polydem/domain/domain_error.h"

namespace polydem::domain {

namespace {

/// The edge h for which about `target` cubes fill `extent`: the product over the axes of
/// max(1, extent_a / h) equals target. Axes thinner than h count as one layer, so a flat pile
/// gets columns rather than slivers.
double firstEdge(const Vec3& extent, double target) {
  std::array<double, 3> e{extent.x(), extent.y(), extent.z()};
  std::sort(e.begin(), e.end(), std::greater<>());
  for (int k = 3; k >= 1; --k) {
    double product = 1.0;
    for (int a = 0; a < k; ++a) product *= e[a];
    const double h = std::pow(product / target, 1.0 / k);
    if (k == 1 || e[k - 1] >= h) return h;
  }
  return e[0] / target;  // not reached
}

struct Grid {
  Index3 counts{1, 1, 1};
  std::int64_t total = 1;
};

}  // namespace

Index3 fitBlockCounts(const Aabb& domain, const Aabb& particles, const BlockFitOptions& options,
                      const OccupiedBlockCount& occupied) {
  if (options.ranks < 1 || options.occupied_per_rank < 1 || options.max_blocks < options.ranks ||
      !(options.min_block_edge >= 0) || !std::isfinite(options.min_block_edge)) {
    throw DomainError(cat("fitBlockCounts: bad options (ranks ", options.ranks,
                          ", occupied per rank ", options.occupied_per_rank, ", min edge ",
                          options.min_block_edge, ", max blocks ", options.max_blocks, ")"));
  }
  const Vec3 length = domain.extent();
  if (!(length.array() > 0).all() || !std::isfinite(length.sum())) {
    throw DomainError("fitBlockCounts: the domain box is empty or not finite");
  }
  double target = static_cast<double>(options.ranks) * options.occupied_per_rank;
  if (options.particles > 0) {
    target = std::min(target, std::max<double>(options.ranks, options.particles / 4));
  }
  // The particles' box, clipped to the domain; an empty or degenerate one falls back to the
  // domain itself (the first edge is then chooseBlockCounts's).
  Aabb box(particles.lo.cwiseMax(domain.lo), particles.hi.cwiseMin(domain.hi));
  const Vec3 extent = box.empty() ? length : box.extent();
  double h = firstEdge(extent.cwiseMax(Vec3::Constant(1e-9 * length.maxCoeff())), target);

  Index3 limit{};
  for (int a = 0; a < 3; ++a) {
    const double most = options.min_block_edge > 0 ? std::floor(length[a] / options.min_block_edge)
                                                   : static_cast<double>(INT_MAX);
    limit[a] = static_cast<int>(std::clamp(most, 1.0, static_cast<double>(INT_MAX)));
  }
  auto gridFor = [&](double edge) {
    Grid g;
    double total = 1.0;
    for (int a = 0; a < 3; ++a) {
      const double n = std::clamp(std::round(length[a] / edge), 1.0, static_cast<double>(limit[a]));
      g.counts[a] = static_cast<int>(n);
      total *= n;
    }
    g.total = total > 9e18 ? INT64_MAX : static_cast<std::int64_t>(total);
    return g;
  };
  const double step = std::cbrt(2.0);
  while (gridFor(h).total > options.max_blocks) h *= step;

  Grid chosen = gridFor(h), last;
  for (int k = 0; k < 256; ++k, h /= step) {
    const Grid g = gridFor(h);
    if (g.total > options.max_blocks) break;
    if (k > 0 && g.counts == last.counts) continue;  // rounding: same grid as before
    last = g;
    chosen = g;
    if (static_cast<double>(occupied(g.counts)) >= target || g.counts == limit) break;
  }
  if (chosen.total < options.ranks) return chooseBlockCounts(domain, options.ranks, 1);
  return chosen.counts;
}

std::int64_t countOccupiedBlocks(const Aabb& domain, const Index3& counts, const Periodic& periodic,
                                 std::span<const Vec3> points) {
  const BlockForest forest(domain, counts, periodic);
  std::unordered_set<int> seen;
  for (const Vec3& x : points) {
    const int b = forest.blockOf(x);
    if (b >= 0) seen.insert(b);
  }
  return static_cast<std::int64_t>(seen.size());
}

}  // namespace polydem::domain
