// Collective rank-map computation: per-block weights from all ranks -> one map on every rank.
//
// A partition must be identical on every rank. METIS is deterministic for fixed options, but
// rather than rely on that across processes, the map is computed once on rank 0 and broadcast.
#pragma once

#include <mpi.h>

#include <span>
#include <vector>

#include "domain/block_forest.h"

namespace polydem::domain {

enum class PartitionMethod {
  kMetis,  ///< partitionMetis: balanced and with short rank borders
  kSfc,    ///< partitionSfc on the Hilbert curve: no graph partitioner, contiguous chunks
};

/// Collective over `comm`; the map for mpi::size(comm) ranks, identical on every rank.
/// `local_weights` has one entry per block: this rank's contribution (e.g. the number of its
/// owned particles or contacts in each block, 0 elsewhere); the weights partitioned are the sums
/// over all ranks. When the forest's current map is over the same number of ranks, the new parts
/// are renamed to keep as much weight in place as possible (relabelToMatch). Errors (more ranks
/// than blocks, a bad weight on any rank) throw the same DomainError on every rank.
std::vector<int> computeRankMap(const BlockForest& forest, std::span<const double> local_weights,
                                MPI_Comm comm = MPI_COMM_WORLD,
                                PartitionMethod method = PartitionMethod::kMetis);

struct RebalanceReport {
  double imbalance_before = 1.0;  ///< imbalance of the old map (over its own number of ranks)
  double imbalance_after = 1.0;   ///< imbalance of the new map
  int blocks_moved = 0;           ///< blocks whose rank changed
};

/// computeRankMap, then installs the new map in `forest` (collective; every rank gets the same
/// map and the same report). Moving the particles of the moved blocks is the caller's (comm's)
/// job: ownerOf() already answers with the new map.
RebalanceReport rebalance(BlockForest& forest, std::span<const double> local_weights,
                          MPI_Comm comm = MPI_COMM_WORLD,
                          PartitionMethod method = PartitionMethod::kMetis);

}  // namespace polydem::domain
