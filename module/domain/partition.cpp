#include "polydem/domain/partition.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <functional>
#include <tuple>

#include "polydem/core/logging.h"
#include "polydem/core/strings.h"
#include "polydem/domain/domain_error.h"
#include "polydem/domain/partition_checks.h"

namespace polydem::domain {

std::vector<int> vertexWeights(const BlockForest& forest, std::span<const double> weights) {
  detail::checkWeights(forest, weights, "vertexWeights");
  const double w_max = weights.empty() ? 0.0 : *std::max_element(weights.begin(), weights.end());
  const std::int64_t blocks = forest.numBlocks();
  const std::int64_t scale =
      std::max<std::int64_t>(0, std::min<std::int64_t>(kWeightResolution, (1 << 30) / blocks - 1));
  std::vector<int> out(weights.size(), 1);
  if (w_max > 0) {
    for (std::size_t b = 0; b < weights.size(); ++b) {
      out[b] = 1 + static_cast<int>(std::llround(weights[b] / w_max * static_cast<double>(scale)));
    }
  }
  return out;
}

std::vector<int> capHeavyBlocks(std::span<const int> vertex_weights, int ranks) {
  std::vector<int> out(vertex_weights.begin(), vertex_weights.end());
  if (ranks < 1 || static_cast<int>(out.size()) < ranks) return out;
  std::vector<std::int64_t> sorted(out.begin(), out.end());
  std::sort(sorted.begin(), sorted.end(), std::greater<>());
  std::int64_t rest = 0;
  for (std::int64_t w : sorted) rest += w;
  // k heaviest blocks capped: the others share ranks - k ranks. Stop at the first k whose next
  // block fits under that share (k < ranks always: the lightest ranks - k blocks fit somewhere).
  for (int k = 0; k < ranks; ++k) {
    const std::int64_t share = (rest + (ranks - k) - 1) / (ranks - k);  // ceil
    if (sorted[k] <= share) {
      if (k == 0) return out;
      for (int& w : out) w = static_cast<int>(std::min<std::int64_t>(w, share));
      return out;
    }
    rest -= sorted[k];
  }
  return out;
}

BlockGraph blockGraph(const BlockForest& forest) {
  BlockGraph g;
  const int n = forest.numBlocks();
  g.offsets.reserve(n + 1);
  g.offsets.push_back(0);
  std::vector<std::pair<int, int>> links;  // (neighbour, weight) of one block
  for (int b = 0; b < n; ++b) {
    links.clear();
    for (int dz = -1; dz <= 1; ++dz) {
      for (int dy = -1; dy <= 1; ++dy) {
        for (int dx = -1; dx <= 1; ++dx) {
          const int order = std::abs(dx) + std::abs(dy) + std::abs(dz);
          if (order == 0) continue;
          const int nb = forest.neighbourIndex(b, {dx, dy, dz});
          if (nb >= 0 && nb != b) links.emplace_back(nb, 1 << (3 - order));
        }
      }
    }
    std::sort(links.begin(), links.end());
    for (std::size_t i = 0; i < links.size(); ++i) {
      if (i > 0 && links[i].first == links[i - 1].first) {
        g.edge_weights.back() += links[i].second;  // same block through another offset
      } else {
        g.adjacency.push_back(links[i].first);
        g.edge_weights.push_back(links[i].second);
      }
    }
    g.offsets.push_back(static_cast<int>(g.adjacency.size()));
  }
  return g;
}

std::int64_t edgeCut(const BlockGraph& graph, std::span<const int> map) {
  std::int64_t cut = 0;
  for (std::size_t u = 0; u + 1 < graph.offsets.size(); ++u) {
    for (int k = graph.offsets[u]; k < graph.offsets[u + 1]; ++k) {
      if (map[u] != map[graph.adjacency[k]]) cut += graph.edge_weights[k];
    }
  }
  return cut / 2;  // every edge is stored in both directions
}

std::vector<int> partitionSfc(const BlockForest& forest, std::span<const double> weights, int ranks,
                              Curve curve) {
  detail::checkRanks(forest, ranks, "partitionSfc");
  const std::vector<int> vw = capHeavyBlocks(vertexWeights(forest, weights), ranks);
  const int n = forest.numBlocks();
  const std::vector<int> order = sfcOrder(forest, curve);
  std::vector<std::int64_t> prefix(n + 1, 0);  // exact integer sums: no rounding, no ties lost
  for (int k = 0; k < n; ++k) prefix[k + 1] = prefix[k] + vw[order[k]];
  const std::int64_t total = prefix[n];

  std::vector<int> map(n, ranks - 1);
  int start = 0;
  for (int r = 0; r + 1 < ranks; ++r) {
    // The cut c (rank r gets order[start, c)) nearest to the target prefix (r+1)/ranks * total,
    // compared as prefix * ranks against (r+1) * total to stay in integers.
    const std::int64_t target = (r + 1) * total;
    auto dist = [&](int k) { return std::llabs(prefix[k] * ranks - target); };
    int c = static_cast<int>(
        std::lower_bound(prefix.begin() + start, prefix.end(), target,
                         [&](std::int64_t p, std::int64_t t) { return p * ranks < t; }) -
        prefix.begin());
    c = std::min(c, n);
    if (c > start && dist(c - 1) <= dist(c)) --c;
    c = std::clamp(c, start + 1, n - (ranks - 1 - r));
    for (int k = start; k < c; ++k) map[order[k]] = r;
    start = c;
  }
  return map;
}

std::vector<double> rankLoads(std::span<const int> map, std::span<const double> weights,
                              int ranks) {
  if (map.size() != weights.size()) {
    throw DomainError(cat("rankLoads: map has ", map.size(), " entries, weights ", weights.size()));
  }
  std::vector<double> loads(ranks, 0.0);
  for (std::size_t b = 0; b < map.size(); ++b) {
    if (map[b] < 0 || map[b] >= ranks) {
      throw DomainError(
          cat("rankLoads: block ", b, " on rank ", map[b], ", outside [0, ", ranks, ")"));
    }
    loads[map[b]] += weights[b];
  }
  return loads;
}

double imbalance(std::span<const int> map, std::span<const double> weights, int ranks) {
  if (ranks < 1) throw DomainError(cat("imbalance: ", ranks, " ranks"));
  const std::vector<double> loads = rankLoads(map, weights, ranks);
  double total = 0, max_load = 0;
  for (double l : loads) {
    total += l;
    max_load = std::max(max_load, l);
  }
  if (total <= 0) return 1.0;
  return max_load / (total / ranks);
}

int repairEmptyRanks(const BlockForest& forest, std::vector<int>& map,
                     std::span<const double> weights, int ranks) {
  detail::checkRanks(forest, ranks, "repairEmptyRanks");
  detail::checkMap(forest, map, ranks, "repairEmptyRanks");
  const std::vector<int> vw = vertexWeights(forest, weights);
  std::vector<std::int64_t> load(ranks, 0);
  std::vector<int> count(ranks, 0);
  for (int b = 0; b < forest.numBlocks(); ++b) {
    load[map[b]] += vw[b];
    ++count[map[b]];
  }
  int moved = 0;
  for (int empty = 0; empty < ranks; ++empty) {
    if (count[empty] > 0) continue;
    int donor = -1;
    for (int r = 0; r < ranks; ++r) {
      if (count[r] >= 2 && (donor < 0 || load[r] > load[donor])) donor = r;
    }
    // blocks >= ranks and a rank is empty, so some rank has 2 blocks: donor >= 0.
    auto on_border = [&](int b) {
      for (int nb : forest.neighbours(b)) {
        if (map[nb] != donor) return true;
      }
      return false;
    };
    // Best block: on the border if possible, then weight closest to half the donor's load
    // (compared doubled to stay in integers), then lowest index.
    auto key = [&](int b) {
      return std::make_tuple(!on_border(b), std::llabs(2 * std::int64_t{vw[b]} - load[donor]), b);
    };
    int give = -1;
    decltype(key(0)) best{};
    for (int b = 0; b < forest.numBlocks(); ++b) {
      if (map[b] != donor) continue;
      const auto k = key(b);
      if (give < 0 || k < best) {
        give = b;
        best = k;
      }
    }
    map[give] = empty;
    load[donor] -= vw[give];
    load[empty] += vw[give];
    --count[donor];
    ++count[empty];
    ++moved;
  }
  if (moved > 0) {
    log::detail(cat("repairEmptyRanks: moved ", moved, " blocks to ranks METIS left empty"));
  }
  return moved;
}

std::vector<int> relabelToMatch(const BlockForest& forest, std::span<const int> map,
                                std::span<const int> previous, std::span<const double> weights,
                                int ranks) {
  detail::checkMap(forest, map, ranks, "relabelToMatch");
  detail::checkMap(forest, previous, ranks, "relabelToMatch (previous map)");
  const std::vector<int> vw = vertexWeights(forest, weights);
  // Shared weight per (new part, old rank), accumulated over a sorted list: sparse, since each
  // part overlaps only a few old ranks.
  struct Overlap {
    int part, old;
    std::int64_t weight;
  };
  std::vector<Overlap> pairs;
  pairs.reserve(map.size());
  for (std::size_t b = 0; b < map.size(); ++b) pairs.push_back({map[b], previous[b], vw[b]});
  std::sort(pairs.begin(), pairs.end(), [](const Overlap& p, const Overlap& q) {
    return std::tie(p.part, p.old) < std::tie(q.part, q.old);
  });
  std::vector<Overlap> merged;
  for (const Overlap& p : pairs) {
    if (!merged.empty() && merged.back().part == p.part && merged.back().old == p.old) {
      merged.back().weight += p.weight;
    } else {
      merged.push_back(p);
    }
  }
  std::sort(merged.begin(), merged.end(), [](const Overlap& p, const Overlap& q) {
    return std::make_tuple(-p.weight, p.part, p.old) < std::make_tuple(-q.weight, q.part, q.old);
  });
  std::vector<int> label(ranks, -1);
  std::vector<bool> taken(ranks, false);
  for (const Overlap& p : merged) {
    if (label[p.part] < 0 && !taken[p.old]) {
      label[p.part] = p.old;
      taken[p.old] = true;
    }
  }
  int next_free = 0;
  for (int part = 0; part < ranks; ++part) {
    if (label[part] >= 0) continue;
    while (taken[next_free]) ++next_free;
    label[part] = next_free;
    taken[next_free] = true;
  }
  std::vector<int> out(map.size());
  for (std::size_t b = 0; b < map.size(); ++b) out[b] = label[map[b]];
  return out;
}

}  // namespace polydem::domain
