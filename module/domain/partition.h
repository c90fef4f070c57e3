// Block -> rank maps from per-block weights: METIS on the block graph, or a space-filling curve
// cut into chunks of nearly equal weight. All functions here are pure: the same input gives the
// same map on every rank and every run (see rebalance.h for the collective wrapper).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "polydem/domain/block_forest.h"
#include "polydem/domain/space_filling_curve.h"

namespace polydem::domain {

enum class PartitionMethod {
  kMetis,  ///< partitionMetis: balanced and with short rank borders
  kSfc,    ///< partitionSfc on the Hilbert curve: no graph partitioner, contiguous chunks
};

/// Resolution of the integer vertex weights: the heaviest block weighs 1 + kWeightResolution.
inline constexpr int kWeightResolution = 10000;

/// Integer block weights as METIS and partitionSfc see them:
///   vertex_weight[b] = 1 + round(S * weights[b] / max(weights)),  S = kWeightResolution
/// (S is lowered for more than ~1e5 blocks so that the total stays below 2^30 and METIS's 32-bit
/// sums cannot overflow). The +1 floor makes an empty block count as a small cost, so a rank is
/// never handed an arbitrarily large empty region for free and all-zero weights still balance
/// block counts. Weights are per-block costs (particles, contacts, ...): finite and >= 0,
/// otherwise DomainError. Only ratios matter: the result is the same for weights * any factor.
std::vector<int> vertexWeights(const BlockForest& forest, std::span<const double> weights);

/// Vertex weights capped at the fair share, for partitioning over `ranks` ranks. A block heavier
/// than a fair share ends up on a rank of its own in any partition and bounds the maximum load;
/// left at full weight it makes the balance target unreachable, and METIS then leaves parts empty
/// (printing "too many parts") and balances the remaining ranks badly. Capped at the fair share it
/// simply fills one rank. The cap c is the fixed point of water-filling: with the k heaviest
/// blocks above c, c = ceil((total - their weight) / (ranks - k)). No block above c: unchanged.
std::vector<int> capHeavyBlocks(std::span<const int> vertex_weights, int ranks);

/// The block graph in compressed-row form: vertex b's neighbours (BlockForest::neighbours) are
/// adjacency[offsets[b] .. offsets[b+1]). Default edge weight: for every offset d in {-1,0,1}^3
/// that leads from b to the neighbour, add 2^(3 - |dx|-|dy|-|dz|), i.e. 4 per shared face, 2 per
/// shared edge, 1 per shared corner -- roughly the relative volume of ghost layers thin compared
/// to a block. (A periodic axis with 2 blocks links them through two faces: weight 8.)
struct BlockGraph {
  std::vector<int> offsets;
  std::vector<int> adjacency;
  std::vector<int> edge_weights;
};
BlockGraph blockGraph(const BlockForest& forest);
/// Sum of the weights of the graph edges whose ends lie on different ranks.
std::int64_t edgeCut(const BlockGraph& graph, std::span<const int> map);

/// METIS partition of the block graph into `ranks` parts.
/// - Vertex weights: capHeavyBlocks(vertexWeights(weights)); edge weights: blockGraph's, or
///   `edge_weights` if given (aligned with blockGraph(forest).adjacency, symmetric, each >= 1).
/// - Both METIS_PartGraphRecursive and METIS_PartGraphKway are run (cheap on a block graph), each
///   with fixed options: seed 1, edge-cut objective, 4 trial cuts, 10 refinement iterations, the
///   METIS default load tolerances (1.001 recursive, 1.03 k-way), no contiguity constraint.
///   Empty parts are repaired (repairEmptyRanks). The map with the smaller maximum rank load
///   (vertex weights) is kept; on a tie the smaller edge cut, then the recursive one. Recursive
///   bisection tends to win for few ranks and uniform loads, k-way for many ranks and skewed loads.
/// - ranks == 1: every block on rank 0; ranks == blocks: block b on rank b; ranks > blocks:
///   DomainError. If METIS fails, a warning is logged and partitionSfc (Hilbert) is returned.
/// Every rank gets at least one block.
std::vector<int> partitionMetis(const BlockForest& forest, std::span<const double> weights,
                                int ranks, std::span<const int> edge_weights = {});

/// Blocks in `curve` order cut into `ranks` contiguous chunks of nearly equal (capped, see
/// capHeavyBlocks) vertex weight: cut r (r = 1..ranks-1) goes where the prefix sum is closest to
/// r/ranks of the total (the lower position on a tie), moved if needed so that every chunk has at
/// least one block. Every chunk then weighs at most total/ranks + the heaviest capped block. Rank
/// r gets the r-th chunk.
std::vector<int> partitionSfc(const BlockForest& forest, std::span<const double> weights, int ranks,
                              Curve curve = Curve::kHilbert);

/// Sum of `weights` over each rank's blocks (in block order).
std::vector<double> rankLoads(std::span<const int> map, std::span<const double> weights, int ranks);
/// max rank load / mean rank load (>= 1; 1 when all weights are 0).
double imbalance(std::span<const int> map, std::span<const double> weights, int ranks);

/// Gives every rank without a block one block, as long as blocks >= ranks. Rule, per empty rank
/// in ascending order: the donor is the rank with the largest vertex-weight load among those
/// with at least 2 blocks (lowest rank on ties); it gives the block on its border (a neighbour
/// owned by another rank; any block if it has no border) whose vertex weight is closest to half
/// of its load (lowest block index on ties). That never raises the maximum load. Returns the
/// number of blocks moved.
int repairEmptyRanks(const BlockForest& forest, std::vector<int>& map,
                     std::span<const double> weights, int ranks);

/// Renames the parts of `map` so that as much vertex weight as possible stays on the rank that
/// held it in `previous` (both maps over `ranks` ranks): pairs (new part, old rank) are matched
/// greedily by shared weight, largest first (ties: lower part, then lower rank); unmatched parts
/// take the unused ranks in ascending order. The partition itself, and so its imbalance, is
/// unchanged; only the migration volume drops (METIS part numbers are arbitrary).
std::vector<int> relabelToMatch(const BlockForest& forest, std::span<const int> map,
                                std::span<const int> previous, std::span<const double> weights,
                                int ranks);

}  // namespace polydem::domain
