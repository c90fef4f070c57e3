// Collective rank-map computation: per-block weights from all ranks -> one map on every rank.
//
// A partition must be identical on every rank. METIS is deterministic for fixed options, but
// rather than rely on that across processes, the map is computed once on rank 0 and broadcast.
#pragma once

#include <mpi.h>

#include <span>
#include <vector>

#include "polydem/domain/block_forest.h"
#include "polydem/domain/block_loads.h"
#include "polydem/domain/partition.h"

namespace polydem::domain {

/// Collective over `comm`; the map for mpi::size(comm) ranks, identical on every rank.
/// `local_weights` has one entry per block: this rank's contribution (e.g. the number of its
/// owned particles or contacts in each block, 0 elsewhere); the weights partitioned are the sums
/// over all ranks. When the forest's current map is over the same number of ranks, the new parts
/// are renamed to keep as much weight in place as possible (relabelToMatch). Errors (more ranks
/// than blocks, a bad weight on any rank) throw the same DomainError on every rank.
std::vector<int> computeRankMap(const BlockForest& forest, std::span<const double> local_weights,
                                MPI_Comm comm = MPI_COMM_WORLD,
                                PartitionMethod method = PartitionMethod::kMetis);

/// The same for block loads (block_loads.h): this rank's contributions, summed on rank 0 and
/// partitioned there by partitionLoads (which partitions only the box of blocks with work when
/// most of the forest is empty), renamed to match the current map as above.
std::vector<int> computeRankMap(const BlockForest& forest, const BlockLoads& local,
                                MPI_Comm comm = MPI_COMM_WORLD,
                                PartitionMethod method = PartitionMethod::kMetis);

struct RebalanceReport {
  double imbalance_before = 1.0;  ///< imbalance of the old map (over its own number of ranks)
  double imbalance_after = 1.0;   ///< imbalance of the new map
  int blocks_moved = 0;           ///< blocks whose rank changed
};

/// computeRankMap, then installs the new map in `forest` (collective; every rank gets the same
/// map and the same report), unless the current map is over the same ranks and better: a worse
/// map is never installed (imbalance_after is then imbalance_before). Moving the particles of the
/// moved blocks is the caller's (comm's) job: ownerOf() already answers with the new map.
RebalanceReport rebalance(BlockForest& forest, std::span<const double> local_weights,
                          MPI_Comm comm = MPI_COMM_WORLD,
                          PartitionMethod method = PartitionMethod::kMetis);

/// A new decomposition weighed against the current one (proposeBalance).
struct BalanceProposal {
  double imbalance_before = 1.0;  ///< the current map on the current forest, under the loads
  double imbalance_after = 1.0;   ///< the proposed map on the candidate forest
  bool adopted = false;           ///< after * (1 + margin) <= before
  std::vector<int> map;           ///< the proposed map (for the candidate forest)
  int blocks_moved = 0;           ///< blocks of the same forest that change rank; -1: new forest
};

/// Collective over `comm` (every rank gets the same proposal). `current_local` and
/// `candidate_local` are this rank's contributions to the loads of the current forest and of
/// `candidate` (a forest of the same domain; nullptr: the current forest, repartitioned). They
/// are summed on rank 0, which partitions the candidate (partitionLoads), renames the parts to
/// keep as much load as possible on its rank (relabelToMatch; for a new forest, each block
/// compared with the current owner of its centre), and compares the imbalance of the current map
/// with that of the new one. The proposal is adopted only if it lowers the imbalance by the
/// relative `margin`: a partition a few percent better is not worth moving blocks for, and one
/// that is worse (METIS's tolerance, whole blocks) is never adopted. Installing the map is the
/// caller's job. Errors (bad loads on any rank, more ranks than blocks) throw the same
/// DomainError on every rank.
BalanceProposal proposeBalance(const BlockForest& current, const BlockLoads& current_local,
                               const BlockForest* candidate, const BlockLoads* candidate_local,
                               MPI_Comm comm, PartitionMethod method, double margin);

}  // namespace polydem::domain
