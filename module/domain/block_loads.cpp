#include "polydem/domain/block_loads.h"

#include <algorithm>
#include <cmath>
#include <tuple>

#include "polydem/core/strings.h"
#include "polydem/domain/domain_error.h"
#include "polydem/domain/partition_checks.h"

namespace polydem::domain {

namespace {

/// The links of every block as adjacency lists: block b's are (other block, weight) entries
/// offsets[b] .. offsets[b+1].
struct LinkLists {
  std::vector<int> offsets;
  std::vector<std::pair<int, double>> entries;
};

LinkLists linkLists(const BlockLoads& loads) {
  const int n = loads.numBlocks();
  LinkLists l;
  l.offsets.assign(n + 1, 0);
  for (const BlockLink& k : loads.links) {
    ++l.offsets[k.a + 1];
    ++l.offsets[k.b + 1];
  }
  for (int b = 0; b < n; ++b) l.offsets[b + 1] += l.offsets[b];
  l.entries.resize(l.offsets[n]);
  std::vector<int> fill(l.offsets.begin(), l.offsets.end() - 1);
  for (const BlockLink& k : loads.links) {
    l.entries[fill[k.a]++] = {k.b, k.weight};
    l.entries[fill[k.b]++] = {k.a, k.weight};
  }
  return l;
}

void checkLoads(const BlockForest& forest, const BlockLoads& loads, const char* who) {
  detail::checkWeights(forest, loads.self, who);
  for (const BlockLink& k : loads.links) {
    if (k.a < 0 || k.a >= k.b || k.b >= forest.numBlocks() || !(k.weight >= 0) ||
        !std::isfinite(k.weight)) {
      throw DomainError(
          cat(who, ": bad link between blocks ", k.a, " and ", k.b, " (weight ", k.weight, ")"));
    }
  }
}

}  // namespace

void BlockLoads::addPair(int a, int b, double w) {
  if (a == b) {
    self[a] += w;
  } else {
    links.push_back({std::min(a, b), std::max(a, b), w});
  }
}

void BlockLoads::merge() {
  std::stable_sort(links.begin(), links.end(), [](const BlockLink& x, const BlockLink& y) {
    return std::tie(x.a, x.b) < std::tie(y.a, y.b);
  });
  std::vector<BlockLink> merged;
  for (const BlockLink& k : links) {
    if (!merged.empty() && merged.back().a == k.a && merged.back().b == k.b) {
      merged.back().weight += k.weight;
    } else {
      merged.push_back(k);
    }
  }
  links = std::move(merged);
}

std::vector<double> BlockLoads::halfLinkWeights() const {
  std::vector<double> w = self;
  for (const BlockLink& k : links) {
    w[k.a] += 0.5 * k.weight;
    w[k.b] += 0.5 * k.weight;
  }
  return w;
}

std::vector<double> rankLoads(std::span<const int> map, const BlockLoads& loads, int ranks) {
  std::vector<double> load = rankLoads(map, std::span<const double>(loads.self), ranks);
  for (const BlockLink& k : loads.links) {
    load[map[k.a]] += k.weight;
    if (map[k.b] != map[k.a]) load[map[k.b]] += k.weight;
  }
  return load;
}

double imbalance(std::span<const int> map, const BlockLoads& loads, int ranks) {
  if (ranks < 1) throw DomainError(cat("imbalance: ", ranks, " ranks"));
  const std::vector<double> load = rankLoads(map, loads, ranks);
  double total = 0, most = 0;
  for (double l : load) {
    total += l;
    most = std::max(most, l);
  }
  return total > 0 ? most / (total / ranks) : 1.0;
}

std::vector<int> linkEdgeWeights(const BlockForest& forest, const BlockLoads& loads) {
  const BlockGraph graph = blockGraph(forest);
  std::vector<int> out = graph.edge_weights;
  double heaviest = 0;
  for (const BlockLink& k : loads.links) heaviest = std::max(heaviest, k.weight);
  if (heaviest <= 0) return out;
  constexpr double kScale = 1000;
  for (int u = 0; u + 1 < static_cast<int>(graph.offsets.size()); ++u) {
    for (int e = graph.offsets[u]; e < graph.offsets[u + 1]; ++e) {
      const int v = graph.adjacency[e];
      const BlockLink key{std::min(u, v), std::max(u, v), 0.0};
      const auto it = std::lower_bound(loads.links.begin(), loads.links.end(), key,
                                       [](const BlockLink& x, const BlockLink& y) {
                                         return std::tie(x.a, x.b) < std::tie(y.a, y.b);
                                       });
      if (it != loads.links.end() && it->a == key.a && it->b == key.b) {
        out[e] += static_cast<int>(std::lround(kScale * it->weight / heaviest));
      }
    }
  }
  return out;
}

int refineMaxLoad(const BlockForest& forest, const BlockLoads& loads, std::vector<int>& map,
                  int ranks) {
  checkLoads(forest, loads, "refineMaxLoad");
  detail::checkMap(forest, map, ranks, "refineMaxLoad");
  const int n = forest.numBlocks();
  const BlockGraph graph = blockGraph(forest);
  const LinkLists links = linkLists(loads);
  // The work block b takes along when it leaves rank `from`, and brings when it joins rank `to`:
  // its own, and its links to blocks not on that rank. No other rank's load changes.
  auto carried = [&](int b, int rank) {
    double w = loads.self[b];
    for (int k = links.offsets[b]; k < links.offsets[b + 1]; ++k) {
      if (map[links.entries[k].first] != rank) w += links.entries[k].second;
    }
    return w;
  };
  std::vector<double> load = rankLoads(map, loads, ranks);
  std::vector<std::vector<int>> blocks_of(ranks);
  for (int b = 0; b < n; ++b) blocks_of[map[b]].push_back(b);
  int moves = 0;
  for (int iteration = 0; iteration < 2 * n; ++iteration) {
    const int r = static_cast<int>(std::max_element(load.begin(), load.end()) - load.begin());
    if (blocks_of[r].size() < 2 || load[r] <= 0) break;
    // Best move: smallest resulting max(load r, load s); it must lower load r's level.
    std::tuple<double, int, int> best{load[r] * (1 - 1e-12), -1, -1};
    double best_rest = 0, best_grown = 0;
    for (int b : blocks_of[r]) {
      const double rest = load[r] - carried(b, r);
      for (int e = graph.offsets[b]; e < graph.offsets[b + 1]; ++e) {
        const int s = map[graph.adjacency[e]];
        if (s == r) continue;
        const double grown = load[s] + carried(b, s);
        const std::tuple<double, int, int> candidate{std::max(rest, grown), b, s};
        if (candidate < best) {
          best = candidate;
          best_rest = rest;
          best_grown = grown;
        }
      }
    }
    const auto [level, b, s] = best;
    if (b < 0) break;
    map[b] = s;
    load[r] = best_rest;
    load[s] = best_grown;
    auto& from = blocks_of[r];
    from.erase(std::find(from.begin(), from.end(), b));
    blocks_of[s].push_back(b);
    ++moves;
  }
  return moves;
}

namespace {

/// The blocks with work, one block wider on every side, as an inclusive range of block
/// coordinates; false if no block has work.
bool workRange(const BlockForest& forest, const BlockLoads& loads, Index3& lo, Index3& hi) {
  const Index3& n = forest.counts();
  lo = n;
  hi = {-1, -1, -1};
  auto grow = [&](int b) {
    const Index3 c = forest.blockCoords(b);
    for (int a = 0; a < 3; ++a) {
      lo[a] = std::min(lo[a], c[a]);
      hi[a] = std::max(hi[a], c[a]);
    }
  };
  for (int b = 0; b < forest.numBlocks(); ++b) {
    if (loads.self[b] > 0) grow(b);
  }
  for (const BlockLink& k : loads.links) {
    grow(k.a);
    grow(k.b);
  }
  if (hi[0] < 0) return false;
  for (int a = 0; a < 3; ++a) {
    lo[a] = std::max(0, lo[a] - 1);
    hi[a] = std::min(n[a] - 1, hi[a] + 1);
  }
  return true;
}

std::vector<int> partitionAll(const BlockForest& forest, const BlockLoads& loads, int ranks,
                              PartitionMethod method) {
  const std::vector<double> weights = loads.halfLinkWeights();
  std::vector<int> map =
      method == PartitionMethod::kMetis
          ? partitionMetis(forest, weights, ranks, linkEdgeWeights(forest, loads))
          : partitionSfc(forest, weights, ranks, Curve::kHilbert);
  refineMaxLoad(forest, loads, map, ranks);
  return map;
}

}  // namespace

std::vector<int> partitionLoads(const BlockForest& forest, const BlockLoads& loads, int ranks,
                                PartitionMethod method) {
  checkLoads(forest, loads, "partitionLoads");
  Index3 lo, hi;
  if (!workRange(forest, loads, lo, hi)) return partitionAll(forest, loads, ranks, method);
  const Index3 size{hi[0] - lo[0] + 1, hi[1] - lo[1] + 1, hi[2] - lo[2] + 1};
  const std::int64_t inside = std::int64_t{size[0]} * size[1] * size[2];
  if (2 * inside > forest.numBlocks() || inside < ranks) {
    return partitionAll(forest, loads, ranks, method);
  }
  // Most blocks are empty (a pile on a wide floor): partition the box of blocks around the work
  // alone, a graph a fraction of the size, and give every block outside it the rank of the
  // nearest block of the box's border (coordinates clamped into the box).
  const Index3& n = forest.counts();
  Periodic periodic{};
  Vec3 box_lo, box_hi;
  for (int a = 0; a < 3; ++a) {
    periodic[a] = forest.periodic(a) && size[a] == n[a];
    box_lo[a] = forest.blockEdges(a)[lo[a]];
    box_hi[a] = forest.blockEdges(a)[hi[a] + 1];
  }
  const BlockForest sub(Aabb(box_lo, box_hi), size, periodic);
  auto subIndex = [&](int b) {
    const Index3 c = forest.blockCoords(b);
    Index3 s;
    for (int a = 0; a < 3; ++a) s[a] = std::clamp(c[a], lo[a], hi[a]) - lo[a];
    return sub.blockIndex(s);
  };
  BlockLoads sub_loads(sub.numBlocks());
  for (int b = 0; b < forest.numBlocks(); ++b) {
    if (loads.self[b] > 0) sub_loads.self[subIndex(b)] += loads.self[b];
  }
  for (const BlockLink& k : loads.links) sub_loads.addPair(subIndex(k.a), subIndex(k.b), k.weight);
  sub_loads.merge();
  const std::vector<int> sub_map = partitionAll(sub, sub_loads, ranks, method);
  std::vector<int> map(forest.numBlocks());
  for (int b = 0; b < forest.numBlocks(); ++b) map[b] = sub_map[subIndex(b)];
  return map;
}

}  // namespace polydem::domain
