// The decomposition of a Simulation follows its work: blocks sized from where the free particles
// are (domain/block_fit.h), the block -> rank map balanced by the work of the last contact phase
// (sim/load_balance.h, domain/block_loads.h), a new decomposition adopted only when it is
// clearly better. None of it changes a result: pairs are evaluated in their canonical frame and
// summed in uid order whatever rank holds them (contact_phase.h).
#include <algorithm>
#include <bit>
#include <cmath>

#include "polydem/core/error.h"
#include "polydem/core/logging.h"
#include "polydem/core/mpi_env.h"
#include "polydem/core/strings.h"
#include "polydem/domain/block_fit.h"
#include "polydem/domain/rebalance.h"
#include "polydem/sim/simulation.h"

namespace polydem::sim {

namespace {

/// Occupied blocks wanted per rank (domain/block_fit.h): the balancer hands out whole blocks,
/// so a rank's share is made of about this many; 16 keeps the rounding to a block within a few
/// percent of a rank's load.
constexpr int kOccupiedBlocksPerRank = 16;

/// A new decomposition must lower the imbalance (max / mean of the ranks' work) by this
/// fraction to be adopted; below it the moves are not worth their migration, and METIS's own
/// tolerance would otherwise let a worse map replace a better one.
constexpr double kAdoptMargin = 0.02;

/// Occupied blocks of `counts` over the free particles of all ranks (each rank holds some).
std::int64_t occupiedOnAllRanks(const domain::Aabb& box, const domain::Index3& counts,
                                const domain::Periodic& periodic, std::span<const Vec3> mine,
                                MPI_Comm comm) {
  const domain::BlockForest forest(box, counts, periodic);
  std::vector<std::uint64_t> bits((static_cast<std::size_t>(forest.numBlocks()) + 63) / 64, 0);
  for (const Vec3& x : mine) {
    const int b = forest.blockOf(x);
    if (b >= 0) bits[b / 64] |= std::uint64_t{1} << (b % 64);
  }
  MPI_Allreduce(MPI_IN_PLACE, bits.data(), static_cast<int>(bits.size()), MPI_UINT64_T, MPI_BOR,
                comm);
  std::int64_t n = 0;
  for (std::uint64_t w : bits) n += std::popcount(w);
  return n;
}

}  // namespace

std::vector<int> Simulation::rankMap(std::span<const double> weights) const {
  if (scene_.domain.balancer == "cyclic") {
    if (forest_->numBlocks() < ranks_) {
      throw InputError(scene_.file, scene_.domain.line,
                       cat("[domain] has ", forest_->numBlocks(), " blocks for ", ranks_,
                           " ranks: balancer \"cyclic\" needs at least one block per rank"));
    }
    std::vector<int> map(forest_->numBlocks());
    for (int b = 0; b < forest_->numBlocks(); ++b) map[b] = b % ranks_;
    return map;
  }
  domain::BlockLoads loads(forest_->numBlocks());
  loads.self.assign(weights.begin(), weights.end());
  return domain::computeRankMap(*forest_, loads, comm_, partitionMethod());
}

domain::PartitionMethod Simulation::partitionMethod() const {
  return scene_.domain.balancer == "sfc" ? domain::PartitionMethod::kSfc
                                         : domain::PartitionMethod::kMetis;
}

domain::Index3 Simulation::fittedBlockCounts(const domain::Aabb& box,
                                             const domain::Periodic& periodic,
                                             std::span<const Vec3> centroids,
                                             bool collective) const {
  Vec3 lo = Vec3::Constant(INFINITY), hi = Vec3::Constant(-INFINITY);
  for (const Vec3& x : centroids) {
    lo = lo.cwiseMin(x);
    hi = hi.cwiseMax(x);
  }
  std::int64_t particles = static_cast<std::int64_t>(centroids.size());
  if (collective) {
    MPI_Allreduce(MPI_IN_PLACE, lo.data(), 3, MPI_DOUBLE, MPI_MIN, comm_);
    MPI_Allreduce(MPI_IN_PLACE, hi.data(), 3, MPI_DOUBLE, MPI_MAX, comm_);
    particles = mpi::allreduceSum(particles, comm_);
  }
  if (particles == 0) return domain::chooseBlockCounts(box, ranks_, 8);  // nothing to follow
  domain::BlockFitOptions options;
  options.ranks = ranks_;
  options.particles = particles;
  options.occupied_per_rank = kOccupiedBlocksPerRank;
  options.min_block_edge = 2.0 * r_free_;  // a particle diameter
  const domain::Aabb filled = domain::Aabb(lo, hi).inflated(r_free_);
  return domain::fitBlockCounts(box, filled, options, [&](const domain::Index3& counts) {
    return collective ? occupiedOnAllRanks(box, counts, periodic, centroids, comm_)
                      : domain::countOccupiedBlocks(box, counts, periodic, centroids);
  });
}

bool Simulation::balanceDecomposition() {
  if (scene_.domain.balancer == "cyclic") return false;  // a stress test of the borders
  const LoadSample sample = std::move(load_sample_);     // of the last contact phase
  load_sample_ = LoadSample();
  // The imbalance of the work just done: one small reduction, every time.
  double total = sample.work.done, most = sample.work.done;
  MPI_Allreduce(MPI_IN_PLACE, &most, 1, MPI_DOUBLE, MPI_MAX, comm_);
  MPI_Allreduce(MPI_IN_PLACE, &total, 1, MPI_DOUBLE, MPI_SUM, comm_);
  ++balance_log_.checks;
  balance_log_.last_imbalance = total > 0 ? most / (total / ranks_) : 1.0;
  if (balance_log_.last_imbalance <= 1.0 + kAdoptMargin) return false;  // nothing to gain

  // A new forest if the free particles now call for other block counts.
  std::unique_ptr<domain::BlockForest> candidate;
  if (!scene_.domain.blocks) {
    std::vector<Vec3> centroids;
    for (std::size_t i = 0; i < storage_.localCount(); ++i) {
      if (storage_[i].isFree()) centroids.push_back(forest_->wrap(storage_[i].position));
    }
    const auto counts =
        fittedBlockCounts(forest_->domain(), forest_->periodic(), centroids, /*collective=*/true);
    if (counts != forest_->counts()) {
      candidate =
          std::make_unique<domain::BlockForest>(forest_->domain(), counts, forest_->periodic());
    }
  }
  const domain::BlockLoads now = binLoad(*forest_, sample);
  const domain::BlockLoads next = candidate ? binLoad(*candidate, sample) : domain::BlockLoads();
  ++balance_log_.proposals;
  auto proposal =
      domain::proposeBalance(*forest_, now, candidate.get(), candidate ? &next : nullptr, comm_,
                             partitionMethod(), kAdoptMargin);
  const domain::Index3 n = candidate ? candidate->counts() : forest_->counts();
  // A changed map is news; a kept one is detail (--verbose), so that it does not bury the
  // progress line every balance interval.
  const std::string line =
      cat("balance at step ", loop_.step(), ": work imbalance ", num(balance_log_.last_imbalance),
          ", modelled ", num(proposal.imbalance_before), " -> ", num(proposal.imbalance_after),
          " on ", n[0], " x ", n[1], " x ", n[2],
          " blocks: ", proposal.adopted ? "adopted" : "kept the current map");
  if (proposal.adopted) {
    log::info(line);
  } else {
    log::detail(line);
  }
  if (!proposal.adopted) return false;
  if (candidate) forest_ = std::move(candidate);
  forest_->setRankMap(std::move(proposal.map), ranks_);
  ++balance_log_.adopted;
  return true;
}

bool Simulation::rebalance() {
  requireBetweenSteps("rebalance");
  if (!balanceDecomposition()) return false;
  const auto moved = exchange_.migrate(*forest_, storage_, history_, loop_.step());
  migrated_histories_ += moved.histories_received;
  refreshGhosts();
  exchange_totals_ += moved;
  exchange_totals_ += exchange_stats_;
  return true;
}

}  // namespace polydem::sim
