#include "polydem/domain/rebalance.h"

#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

#include "polydem/core/logging.h"
#include "polydem/core/mpi_env.h"
#include "polydem/core/strings.h"
#include "polydem/domain/domain_error.h"
#include "polydem/domain/partition.h"

namespace polydem::domain {

namespace {

/// Runs `compute` on rank 0 and broadcasts its map; an exception on rank 0 becomes the same
/// DomainError on every rank instead of a hang in the broadcast.
template <typename Compute>
std::vector<int> computeOnRootAndBroadcast(int blocks, MPI_Comm comm, Compute&& compute) {
  const bool root = mpi::rank(comm) == 0;
  std::vector<int> map;
  std::string failure;
  if (root) {
    try {
      map = compute();
    } catch (const std::exception& e) {
      failure = e.what();
      if (failure.empty()) failure = "computing the rank map failed on rank 0";
    }
  }
  int failure_length = static_cast<int>(failure.size());
  MPI_Bcast(&failure_length, 1, MPI_INT, 0, comm);
  if (failure_length > 0) {
    failure.resize(failure_length);
    MPI_Bcast(failure.data(), failure_length, MPI_CHAR, 0, comm);
    throw DomainError(failure);
  }
  map.resize(blocks);
  MPI_Bcast(map.data(), blocks, MPI_INT, 0, comm);
  return map;
}

/// Sums every rank's local weights on rank 0 after checking them on every rank.
std::vector<double> reduceWeights(const BlockForest& forest, std::span<const double> local,
                                  MPI_Comm comm) {
  const int blocks = forest.numBlocks();
  std::string problem;
  if (static_cast<int>(local.size()) != blocks) {
    problem = cat(local.size(), " local weights for ", blocks, " blocks");
  } else {
    for (int b = 0; b < blocks && problem.empty(); ++b) {
      if (!(local[b] >= 0) || !std::isfinite(local[b])) {
        problem = cat("block ", b, " has local weight ", local[b]);
      }
    }
  }
  if (mpi::allreduceOr(!problem.empty(), comm)) {
    if (!problem.empty()) log::rankWarning(cat("computeRankMap: ", problem));
    throw DomainError("computeRankMap: bad block weights on at least one rank (" +
                      (problem.empty() ? std::string("see the other ranks' warnings") : problem) +
                      "); weights must be finite, >= 0, one per block");
  }
  std::vector<double> global(mpi::rank(comm) == 0 ? blocks : 0);
  MPI_Reduce(local.data(), global.data(), blocks, MPI_DOUBLE, MPI_SUM, 0, comm);
  return global;
}

/// The new partition (rank 0 only), renamed to match the forest's current map when that map is
/// over the same number of ranks.
std::vector<int> newMap(const BlockForest& forest, const std::vector<double>& weights, int ranks,
                        PartitionMethod method) {
  std::vector<int> map = method == PartitionMethod::kMetis
                             ? partitionMetis(forest, weights, ranks)
                             : partitionSfc(forest, weights, ranks, Curve::kHilbert);
  if (forest.numRanks() == ranks) {
    map = relabelToMatch(forest, map, forest.rankMap(), weights, ranks);
  }
  return map;
}

/// Sums every rank's block loads on rank 0 (merged there; empty on the other ranks) after checking
/// them on every rank.
BlockLoads reduceLoads(const BlockForest& forest, const BlockLoads& local, MPI_Comm comm) {
  const int blocks = forest.numBlocks();
  std::string problem;
  if (local.numBlocks() != blocks) {
    problem = cat(local.numBlocks(), " block loads for ", blocks, " blocks");
  }
  for (const BlockLink& k : local.links) {
    if (problem.empty() && (k.a < 0 || k.a >= k.b || k.b >= blocks || !(k.weight >= 0))) {
      problem = cat("a link between blocks ", k.a, " and ", k.b, " of weight ", k.weight);
    }
  }
  if (mpi::allreduceOr(!problem.empty(), comm)) {
    if (!problem.empty()) log::rankWarning(cat("proposeBalance: ", problem));
    throw DomainError("proposeBalance: bad block loads on at least one rank (" +
                      (problem.empty() ? std::string("see the other ranks' warnings") : problem) +
                      ")");
  }
  const bool root = mpi::rank(comm) == 0;
  BlockLoads global(root ? blocks : 0);
  MPI_Reduce(local.self.data(), global.self.data(), blocks, MPI_DOUBLE, MPI_SUM, 0, comm);
  // The links, a different number per rank, in rank order.
  global.links = mpi::gatherv(local.links, 0, comm);  // empty except on rank 0
  global.merge();
  return global;
}

/// The rank that owns the centre of each block of `next` under the current map: the previous
/// map relabelToMatch compares a partition of a new forest with.
std::vector<int> projectedMap(const BlockForest& current, const BlockForest& next) {
  std::vector<int> map(next.numBlocks());
  for (int b = 0; b < next.numBlocks(); ++b) map[b] = current.ownerOf(next.blockBox(b).center());
  return map;
}

}  // namespace

BalanceProposal proposeBalance(const BlockForest& current, const BlockLoads& current_local,
                               const BlockForest* candidate, const BlockLoads* candidate_local,
                               MPI_Comm comm, PartitionMethod method, double margin) {
  if ((candidate == nullptr) != (candidate_local == nullptr) ||
      (candidate && !(candidate->domain() == current.domain()))) {
    throw DomainError("proposeBalance: a candidate forest needs its loads and the same domain");
  }
  const int ranks = mpi::size(comm);
  const BlockForest& target = candidate ? *candidate : current;
  const BlockLoads now = reduceLoads(current, current_local, comm);
  const BlockLoads next =
      candidate ? reduceLoads(*candidate, *candidate_local, comm) : BlockLoads();
  double figures[2] = {1.0, 1.0};  // imbalance before, after (computed on rank 0)
  BalanceProposal p;
  p.map = computeOnRootAndBroadcast(target.numBlocks(), comm, [&] {
    const BlockLoads& loads = candidate ? next : now;
    std::vector<int> map = partitionLoads(target, loads, ranks, method);
    // A map over another rank count (the one-rank map of a new forest) is no partition to keep.
    const bool comparable = current.numRanks() == ranks;
    if (comparable) {
      const std::vector<int> previous =
          candidate ? projectedMap(current, target) : current.rankMap();
      map = relabelToMatch(target, map, previous, loads.halfLinkWeights(), ranks);
    }
    figures[0] = comparable ? imbalance(current.rankMap(), now, ranks)
                            : std::numeric_limits<double>::infinity();
    figures[1] = imbalance(map, loads, ranks);
    return map;
  });
  MPI_Bcast(figures, 2, MPI_DOUBLE, 0, comm);
  p.imbalance_before = figures[0];
  p.imbalance_after = figures[1];
  p.adopted = p.imbalance_after * (1 + margin) <= p.imbalance_before;
  if (candidate) {
    p.blocks_moved = -1;
  } else {
    for (int b = 0; b < target.numBlocks(); ++b)
      p.blocks_moved += p.map[b] != current.rankOfBlock(b);
  }
  return p;
}

std::vector<int> computeRankMap(const BlockForest& forest, std::span<const double> local_weights,
                                MPI_Comm comm, PartitionMethod method) {
  const int ranks = mpi::size(comm);
  const std::vector<double> weights = reduceWeights(forest, local_weights, comm);
  return computeOnRootAndBroadcast(forest.numBlocks(), comm,
                                   [&] { return newMap(forest, weights, ranks, method); });
}

std::vector<int> computeRankMap(const BlockForest& forest, const BlockLoads& local, MPI_Comm comm,
                                PartitionMethod method) {
  const int ranks = mpi::size(comm);
  const BlockLoads loads = reduceLoads(forest, local, comm);
  return computeOnRootAndBroadcast(forest.numBlocks(), comm, [&] {
    std::vector<int> map = partitionLoads(forest, loads, ranks, method);
    if (forest.numRanks() == ranks) {
      map = relabelToMatch(forest, map, forest.rankMap(), loads.halfLinkWeights(), ranks);
    }
    return map;
  });
}

RebalanceReport rebalance(BlockForest& forest, std::span<const double> local_weights, MPI_Comm comm,
                          PartitionMethod method) {
  const int ranks = mpi::size(comm);
  const int blocks = forest.numBlocks();
  const std::vector<double> weights = reduceWeights(forest, local_weights, comm);
  double figures[2] = {1.0, 1.0};  // imbalance before, after (computed on rank 0)
  std::vector<int> map = computeOnRootAndBroadcast(blocks, comm, [&] {
    std::vector<int> m = newMap(forest, weights, ranks, method);
    figures[0] = imbalance(forest.rankMap(), weights, forest.numRanks());
    figures[1] = imbalance(m, weights, ranks);
    // A map over the same ranks that is worse than the current one is not installed.
    if (forest.numRanks() == ranks && figures[1] > figures[0]) {
      figures[1] = figures[0];
      return forest.rankMap();
    }
    return m;
  });
  MPI_Bcast(figures, 2, MPI_DOUBLE, 0, comm);
  RebalanceReport report;
  report.imbalance_before = figures[0];
  report.imbalance_after = figures[1];
  for (int b = 0; b < blocks; ++b) report.blocks_moved += map[b] != forest.rankOfBlock(b);
  forest.setRankMap(std::move(map), ranks);
  char line[160];
  std::snprintf(line, sizeof line, "rebalance: imbalance %.3f -> %.3f, %d of %d blocks moved",
                report.imbalance_before, report.imbalance_after, report.blocks_moved, blocks);
  log::info(line);
  return report;
}

}  // namespace polydem::domain
