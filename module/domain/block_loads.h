// The work of a step, attributed to blocks, and partitions that balance it.
//
// A rank evaluates every pair that has a particle in one of its blocks, so a pair whose two
// particles lie in blocks of two ranks is evaluated on both (sim/contact_phase.h: no force is
// sent back). Per-block weights cannot express that: the same pair costs its full price on each
// side of a rank border, and how many such pairs a rank has depends on the partition. On a pack
// of a few hundred particles per rank those duplicates are a quarter of a rank's pairs, and a rank
// with four borders does 25 % more work than one in a corner with two. BlockLoads therefore keeps
// the work a block does alone (its particles and the pairs inside it) apart from the work of the
// pairs between two blocks, and a rank's load counts every pair with a particle in its blocks:
//
//   load(r) = sum over blocks b of r of self(b) + sum over links (b, c) with b or c on r of w(b,c)
//
// partitionLoads partitions with METIS (vertex weight self + half of the block's links, edge
// weight the links: the duplicated work a cut costs), then moves border blocks off the most
// loaded rank while that lowers the maximum load (refineMaxLoad).
#pragma once

#include <span>
#include <vector>

#include "polydem/domain/block_forest.h"
#include "polydem/domain/partition.h"

namespace polydem::domain {

/// Work shared by two blocks (a < b): pairs with one particle in each.
struct BlockLink {
  int a = -1, b = -1;
  double weight = 0.0;
};

struct BlockLoads {
  std::vector<double> self;      // per block: its particles and the pairs inside it
  std::vector<BlockLink> links;  // after merge(): sorted by (a, b), each pair of blocks once

  BlockLoads() = default;
  explicit BlockLoads(int blocks) : self(blocks, 0.0) {}
  int numBlocks() const { return static_cast<int>(self.size()); }
  /// Work `w` of a pair with a particle in block a and one in block b (a == b: inside a block).
  void addPair(int a, int b, double w);
  /// Sorts the links and sums those between the same two blocks (in the order added).
  void merge();
  /// self(b) plus half of every link of b: the load per block if no pair were duplicated.
  std::vector<double> halfLinkWeights() const;
};

/// The load of every rank under `map`, duplicated pairs counted on both ranks (formula above).
/// `loads` must be merged. DomainError for a map that does not fit.
std::vector<double> rankLoads(std::span<const int> map, const BlockLoads& loads, int ranks);
/// max rank load / mean rank load under `map` (1 when there is no work).
double imbalance(std::span<const int> map, const BlockLoads& loads, int ranks);

/// METIS edge weights aligned with blockGraph(forest).adjacency: the geometric weight (4 per
/// face, 2 per edge, 1 per corner) plus the link's weight scaled so that the heaviest link adds
/// 1000. A cut through the pile then costs what it duplicates; one through empty space costs
/// about what an empty block border always did.
std::vector<int> linkEdgeWeights(const BlockForest& forest, const BlockLoads& loads);

/// Greedy refinement of `map` for the maximum load: while some move lowers it, the most loaded
/// rank gives one of its blocks on a border with another rank to that rank, choosing the move
/// that leaves the smaller of the two new loads' maximum (ties: lower block, then lower rank). A
/// rank keeps at least one block. Deterministic. Returns the number of moves.
int refineMaxLoad(const BlockForest& forest, const BlockLoads& loads, std::vector<int>& map,
                  int ranks);

/// partitionMetis (vertex weights halfLinkWeights, edge weights linkEdgeWeights) or partitionSfc
/// (Hilbert, same vertex weights), then refineMaxLoad. When the blocks with work, one block
/// wider on every side, span less than half the forest (a pile on a wide floor, in a default
/// domain inflated around it), only that box of blocks is partitioned, and every block outside it
/// goes to the rank of the box's border block nearest to it (coordinates clamped into the box):
/// the graph METIS sees stays the size of the pile, not of the domain.
std::vector<int> partitionLoads(const BlockForest& forest, const BlockLoads& loads, int ranks,
                                PartitionMethod method = PartitionMethod::kMetis);

}  // namespace polydem::domain
