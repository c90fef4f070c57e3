// Load balancing (sim/load_balancing.h): the work recorded, a better decomposition adopted.
#include <algorithm>
#include <bit>
#include <cmath>

#include "polydem/core/error.h"
#include "polydem/core/logging.h"
#include "polydem/core/mpi_env.h"
#include "polydem/core/strings.h"
#include "polydem/domain/block_fit.h"
#include "polydem/domain/rebalance.h"
#include "polydem/sim/load_balancing.h"
#include "polydem/sim/step/operators.h"

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

std::vector<int> rankMap(const StepState& s, std::span<const double> weights) {
  if (s.scene.domain.balancer == "cyclic") {
    if (s.forest->numBlocks() < s.ranks) {
      throw InputError(s.scene.file, s.scene.domain.line,
                       cat("[domain] has ", s.forest->numBlocks(), " blocks for ", s.ranks,
                           " ranks: balancer \"cyclic\" needs at least one block per rank"));
    }
    std::vector<int> map(s.forest->numBlocks());
    for (int b = 0; b < s.forest->numBlocks(); ++b) map[b] = b % s.ranks;
    return map;
  }
  domain::BlockLoads loads(s.forest->numBlocks());
  loads.self.assign(weights.begin(), weights.end());
  return domain::computeRankMap(*s.forest, loads, s.comm, partitionMethod(s));
}

domain::PartitionMethod partitionMethod(const StepState& s) {
  return s.scene.domain.balancer == "sfc" ? domain::PartitionMethod::kSfc
                                          : domain::PartitionMethod::kMetis;
}

domain::Index3 fittedBlockCounts(const StepState& s, const domain::Aabb& box,
                                 const domain::Periodic& periodic, std::span<const Vec3> centroids,
                                 bool collective) {
  Vec3 lo = Vec3::Constant(INFINITY), hi = Vec3::Constant(-INFINITY);
  for (const Vec3& x : centroids) {
    lo = lo.cwiseMin(x);
    hi = hi.cwiseMax(x);
  }
  std::int64_t particles = static_cast<std::int64_t>(centroids.size());
  if (collective) {
    MPI_Allreduce(MPI_IN_PLACE, lo.data(), 3, MPI_DOUBLE, MPI_MIN, s.comm);
    MPI_Allreduce(MPI_IN_PLACE, hi.data(), 3, MPI_DOUBLE, MPI_MAX, s.comm);
    particles = mpi::allreduceSum(particles, s.comm);
  }
  if (particles == 0) return domain::chooseBlockCounts(box, s.ranks, 8);  // nothing to follow
  domain::BlockFitOptions options;
  options.ranks = s.ranks;
  options.particles = particles;
  options.occupied_per_rank = kOccupiedBlocksPerRank;
  options.min_block_edge = 2.0 * s.r_free;  // a particle diameter
  const domain::Aabb filled = domain::Aabb(lo, hi).inflated(s.r_free);
  return domain::fitBlockCounts(box, filled, options, [&](const domain::Index3& counts) {
    return collective ? occupiedOnAllRanks(box, counts, periodic, centroids, s.comm)
                      : domain::countOccupiedBlocks(box, counts, periodic, centroids);
  });
}

void LoadBalancer::record(const particles::ParticleStorage& storage,
                          const std::vector<PairWork>& work, bool sample) {
  if (sample) {
    sample_ = sampleLoad(storage, work, model_);
    last_work_ = sample_.work;
    sample_next_ = false;
  } else {
    last_work_ = stepWork(storage, work, model_);
  }
}

bool LoadBalancer::adopt(StepState& s) {
  if (s.scene.domain.balancer == "cyclic") return false;  // a stress test of the borders
  const LoadSample sample = std::move(sample_);           // of the last contact phase
  sample_ = LoadSample();
  // The imbalance of the work just done: one small reduction, every time.
  double total = sample.work.done, most = sample.work.done;
  MPI_Allreduce(MPI_IN_PLACE, &most, 1, MPI_DOUBLE, MPI_MAX, s.comm);
  MPI_Allreduce(MPI_IN_PLACE, &total, 1, MPI_DOUBLE, MPI_SUM, s.comm);
  ++log_.checks;
  log_.last_imbalance = total > 0 ? most / (total / s.ranks) : 1.0;
  if (log_.last_imbalance <= 1.0 + kAdoptMargin) return false;  // nothing to gain

  // A new forest if the free particles now call for other block counts.
  std::unique_ptr<domain::BlockForest> candidate;
  if (!s.scene.domain.blocks) {
    std::vector<Vec3> centroids;
    for (std::size_t i = 0; i < s.storage.localCount(); ++i) {
      if (s.storage[i].isFree()) centroids.push_back(s.forest->wrap(s.storage[i].position));
    }
    const auto counts = fittedBlockCounts(s, s.forest->domain(), s.forest->periodic(), centroids,
                                          /*collective=*/true);
    if (counts != s.forest->counts()) {
      candidate =
          std::make_unique<domain::BlockForest>(s.forest->domain(), counts, s.forest->periodic());
    }
  }
  const domain::BlockLoads now = binLoad(*s.forest, sample);
  const domain::BlockLoads next = candidate ? binLoad(*candidate, sample) : domain::BlockLoads();
  ++log_.proposals;
  auto proposal =
      domain::proposeBalance(*s.forest, now, candidate.get(), candidate ? &next : nullptr, s.comm,
                             partitionMethod(s), kAdoptMargin);
  const domain::Index3 n = candidate ? candidate->counts() : s.forest->counts();
  // A changed map is news; a kept one is detail (--verbose), so that it does not bury the
  // progress line every balance interval.
  const std::string line =
      cat("balance at step ", s.loop.step(), ": work imbalance ", num(log_.last_imbalance),
          ", modelled ", num(proposal.imbalance_before), " -> ", num(proposal.imbalance_after),
          " on ", n[0], " x ", n[1], " x ", n[2],
          " blocks: ", proposal.adopted ? "adopted" : "kept the current map");
  if (proposal.adopted) {
    log::info(line);
  } else {
    log::detail(line);
  }
  if (!proposal.adopted) return false;
  if (candidate) s.forest = std::move(candidate);
  s.forest->setRankMap(std::move(proposal.map), s.ranks);
  ++log_.adopted;
  return true;
}

bool LoadBalancer::rebalance(StepState& s) {
  if (!adopt(s)) return false;
  const auto moved = s.exchange.migrate(*s.forest, s.storage, s.history, s.loop.step());
  s.migrated_histories += moved.histories_received;
  refreshGhosts(s);
  s.exchange_totals += moved;
  s.exchange_totals += s.exchange_stats;
  return true;
}

}  // namespace polydem::sim
