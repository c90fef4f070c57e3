// partitionMetis: METIS on the block graph, recursive bisection and k-way, the better one kept.
#include <metis.h>

#include <algorithm>
#include <cstdint>
#include <optional>
#include <tuple>

#include "polydem/core/logging.h"
#include "polydem/core/strings.h"
#include "polydem/domain/partition.h"
#include "polydem/domain/partition_checks.h"

namespace polydem::domain {

namespace {

static_assert(sizeof(idx_t) >= sizeof(int), "METIS idx_t narrower than int");

/// Replaces the default edge weights after checking length, sign and symmetry.
void installEdgeWeights(BlockGraph& graph, std::span<const int> edge_weights) {
  if (edge_weights.size() != graph.adjacency.size()) {
    throw DomainError(cat("partitionMetis: ", edge_weights.size(), " edge weights for ",
                          graph.adjacency.size(), " graph edges (blockGraph(forest).adjacency)"));
  }
  const int n = static_cast<int>(graph.offsets.size()) - 1;
  for (int u = 0; u < n; ++u) {
    for (int k = graph.offsets[u]; k < graph.offsets[u + 1]; ++k) {
      const int v = graph.adjacency[k];
      const auto first = graph.adjacency.begin() + graph.offsets[v];
      const auto last = graph.adjacency.begin() + graph.offsets[v + 1];
      const auto back = std::lower_bound(first, last, u);  // neighbour lists are sorted
      const int w_uv = edge_weights[k];
      const int w_vu = edge_weights[back - graph.adjacency.begin()];
      if (w_uv < 1) {
        throw DomainError(cat("partitionMetis: edge weight ", w_uv, " between blocks ", u, " and ",
                              v, "; edge weights must be >= 1"));
      }
      if (w_uv != w_vu) {
        throw DomainError(cat("partitionMetis: edge weights are not symmetric: ", u, "->", v,
                              " is ", w_uv, ", ", v, "->", u, " is ", w_vu));
      }
    }
  }
  graph.edge_weights.assign(edge_weights.begin(), edge_weights.end());
}

/// One METIS call with the fixed options; the part of every block, or nothing if METIS failed.
std::optional<std::vector<int>> runMetis(bool recursive, const BlockGraph& graph,
                                         std::span<const int> vertex_weights, int ranks) {
  std::vector<idx_t> xadj(graph.offsets.begin(), graph.offsets.end());
  std::vector<idx_t> adjncy(graph.adjacency.begin(), graph.adjacency.end());
  std::vector<idx_t> adjwgt(graph.edge_weights.begin(), graph.edge_weights.end());
  std::vector<idx_t> vwgt(vertex_weights.begin(), vertex_weights.end());
  std::vector<idx_t> part(vwgt.size(), 0);
  idx_t nvtxs = static_cast<idx_t>(vwgt.size()), ncon = 1, nparts = ranks, edgecut = 0;

  idx_t options[METIS_NOPTIONS];
  METIS_SetDefaultOptions(options);
  options[METIS_OPTION_SEED] = 1;
  options[METIS_OPTION_OBJTYPE] = METIS_OBJTYPE_CUT;
  options[METIS_OPTION_NCUTS] = 4;
  options[METIS_OPTION_NITER] = 10;
  options[METIS_OPTION_UFACTOR] = recursive ? 1 : 30;
  options[METIS_OPTION_CONTIG] = 0;
  options[METIS_OPTION_NUMBERING] = 0;
  options[METIS_OPTION_DBGLVL] = 0;

  const int status =
      recursive ? METIS_PartGraphRecursive(&nvtxs, &ncon, xadj.data(), adjncy.data(), vwgt.data(),
                                           nullptr, adjwgt.data(), &nparts, nullptr, nullptr,
                                           options, &edgecut, part.data())
                : METIS_PartGraphKway(&nvtxs, &ncon, xadj.data(), adjncy.data(), vwgt.data(),
                                      nullptr, adjwgt.data(), &nparts, nullptr, nullptr, options,
                                      &edgecut, part.data());
  if (status != METIS_OK) {
    log::warning(cat("partitionMetis: METIS_PartGraph", recursive ? "Recursive" : "Kway",
                     " failed (status ", status, ") for ", vwgt.size(), " blocks on ", ranks,
                     " ranks"));
    return std::nullopt;
  }
  for (idx_t p : part) {
    if (p < 0 || p >= ranks) {
      log::warning(cat("partitionMetis: METIS returned part ", p, " for ", ranks, " ranks"));
      return std::nullopt;
    }
  }
  return std::vector<int>(part.begin(), part.end());
}

std::int64_t maxLoad(std::span<const int> map, std::span<const int> vertex_weights, int ranks) {
  std::vector<std::int64_t> load(ranks, 0);
  for (std::size_t b = 0; b < map.size(); ++b) load[map[b]] += vertex_weights[b];
  return *std::max_element(load.begin(), load.end());
}

}  // namespace

std::vector<int> partitionMetis(const BlockForest& forest, std::span<const double> weights,
                                int ranks, std::span<const int> edge_weights) {
  detail::checkRanks(forest, ranks, "partitionMetis");
  const std::vector<int> vw = vertexWeights(forest, weights);
  const int n = forest.numBlocks();
  if (ranks == 1) return std::vector<int>(n, 0);
  if (ranks == n) {
    std::vector<int> map(n);
    for (int b = 0; b < n; ++b) map[b] = b;
    return map;
  }
  BlockGraph graph = blockGraph(forest);
  if (!edge_weights.empty()) installEdgeWeights(graph, edge_weights);
  const std::vector<int> capped = capHeavyBlocks(vw, ranks);

  std::optional<std::vector<int>> best;
  std::tuple<std::int64_t, std::int64_t> best_key{};
  for (bool recursive : {true, false}) {
    std::optional<std::vector<int>> map = runMetis(recursive, graph, capped, ranks);
    if (!map) continue;
    repairEmptyRanks(forest, *map, weights, ranks);
    const auto key = std::make_tuple(maxLoad(*map, vw, ranks), edgeCut(graph, *map));
    if (!best || key < best_key) {
      best = std::move(map);
      best_key = key;
    }
  }
  if (!best) {
    log::warning(cat("partitionMetis: METIS failed for ", n, " blocks on ", ranks,
                     " ranks; using the Hilbert-curve partition instead"));
    return partitionSfc(forest, weights, ranks, Curve::kHilbert);
  }
  return std::move(*best);
}

}  // namespace polydem::domain
