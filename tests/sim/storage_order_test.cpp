// Storage order is free (particles/particle_storage.h): pairs are evaluated and forces summed in
// uid order, so a rank may keep its particles in any order. Checked here on any rank count: a run
// whose particles are shuffled in storage every few steps, one sorted into cell order at every
// step and one every 100 steps all end in the bits of a run never reordered, on one rank
// and on all. And the step's sort leaves the particles in the order it claims: that of the grid
// of the free particles' size (broadphase/cell_order.h), which the broad phase then gathers
// front to back.
#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>
#include <random>

#include "polydem/broadphase/cell_order.h"
#include "polydem/core/logging.h"
#include "polydem/core/mpi_env.h"
#include "polydem/sim/simulation.h"
#include "sliding_heap.h"

namespace polydem::sim {
namespace {

setup::Setup heap(std::int64_t sort_every) {
  setup::Setup s = testing::slidingHeap("mixed", 0.15);
  s.steps = 4000;
  s.domain.sort_every = sort_every;
  return s;
}

struct Outcome {
  std::uint64_t hash = 0;
  std::int64_t pairs = 0, conflicts = 0;
  std::int64_t sorts = 0;     // the step's own sorts, over all ranks
  std::int64_t shuffled = 0;  // particles the shuffles moved, over all ranks
};

// A random permutation of this rank's local particles.
std::vector<std::int32_t> shuffledOrder(const Simulation& sim, std::mt19937_64& rng) {
  std::vector<std::int32_t> order(sim.particles().localCount());
  std::iota(order.begin(), order.end(), 0);
  std::shuffle(order.begin(), order.end(), rng);
  return order;
}

// Runs `scene` on `comm`; with `shuffle`, the local particles are put in a random order every
// 7 steps.
Outcome run(const setup::Setup& scene, bool shuffle, MPI_Comm comm) {
  Simulation sim(scene, comm);
  std::mt19937_64 rng(1234 + static_cast<std::uint64_t>(mpi::rank(comm)));
  std::int64_t shuffled = 0;
  for (std::int64_t k = 0; k < *scene.steps; ++k) {
    if (shuffle && k % 7 == 3) {
      const auto order = shuffledOrder(sim, rng);
      for (std::size_t i = 0; i < order.size(); ++i) shuffled += order[i] != std::int32_t(i);
      sim.reorderParticles(order);
    }
    sim.step();
  }
  const auto h = sim.stateHash();
  return {h.combined, h.pair_count, h.history_conflicts, mpi::allreduceSum(sim.sorts(), comm),
          mpi::allreduceSum(shuffled, comm)};
}

TEST(StorageOrder, ShuffledOrSortedStorageKeepsEveryBit) {
  log::setLevel(log::Level::kWarning);
  // The reference: never reordered, on rank 0 alone.
  Outcome reference;
  MPI_Comm self;
  MPI_Comm_split(MPI_COMM_WORLD, mpi::rank() == 0 ? 0 : MPI_UNDEFINED, 0, &self);
  if (self != MPI_COMM_NULL) {
    reference = run(heap(0), false, self);
    MPI_Comm_free(&self);
  }
  MPI_Bcast(&reference, sizeof reference, MPI_BYTE, 0, MPI_COMM_WORLD);
  EXPECT_EQ(reference.sorts, 0);
  EXPECT_GT(reference.pairs, 10) << "the heap should hold many contact histories";

  const Outcome shuffled = run(heap(0), true, MPI_COMM_WORLD);
  EXPECT_GT(shuffled.shuffled, 1000) << "the shuffles should move particles";
  EXPECT_EQ(shuffled.sorts, 0);
  const Outcome every_step = run(heap(1), false, MPI_COMM_WORLD);
  EXPECT_GE(every_step.sorts, *heap(1).steps) << "a sort at every step (on some rank)";
  const Outcome every_100 = run(heap(100), false, MPI_COMM_WORLD);
  EXPECT_GE(every_100.sorts, 15);
  for (const Outcome* o : {&shuffled, &every_step, &every_100}) {
    EXPECT_EQ(o->hash, reference.hash)
        << "state differs from the never reordered 1-rank run on " << mpi::size() << " ranks";
    EXPECT_EQ(o->conflicts, 0);
  }
}

// The heap's free particles of one size (cubes) at rest, without gravity: a step moves nothing,
// so after it the storage must be exactly in the order the step sorted it into.
TEST(StorageOrder, TheStepLeavesTheGridsCellOrder) {
  log::setLevel(log::Level::kWarning);
  setup::Setup scene = testing::slidingHeap("cubes", 0.15);
  for (auto& p : scene.particles) p.velocity = p.angular_velocity = Vec3::Zero();
  scene.gravity = Vec3::Zero();
  scene.domain.sort_every = 1;
  Simulation sim(scene, MPI_COMM_WORLD);
  std::mt19937_64 rng(77 + static_cast<std::uint64_t>(mpi::rank()));
  sim.reorderParticles(shuffledOrder(sim, rng));

  // The grid order of the current storage, as the step computes it (sim/step/sort.cpp).
  auto gridOrder = [&] {
    const auto& storage = sim.particles();
    std::vector<Vec3> centers;
    std::vector<double> radii;
    std::vector<Uid> uids;
    std::vector<std::uint8_t> active;
    double r_min = INFINITY, r_max = 0.0, r_free = 0.0;
    for (std::size_t i = 0; i < storage.size(); ++i) {
      const auto& p = storage[i];
      centers.push_back(storage.placedPosition(i));
      radii.push_back(sim.shapes()[p.shape].circumradius);
      uids.push_back(p.uid);
      active.push_back(i < storage.localCount() && p.isFree());
      r_max = std::max(r_max, radii.back());
      if (p.isFree()) r_free = std::max(r_free, radii.back());
      if (active.back()) r_min = std::min(r_min, radii.back());
    }
    const double reach = 2.0 * r_min + scene.contact_margin * r_free + 1e-9 * 2.0 * r_max;
    broadphase::CellOrder cells;
    const auto order = cells.order({centers, radii, uids, active}, storage.localCount(), reach);
    return std::vector<std::int32_t>(order.begin(), order.end());
  };
  auto outOfPlace = [](const std::vector<std::int32_t>& order) {
    std::int64_t n = 0;
    for (std::size_t k = 0; k < order.size(); ++k) n += order[k] != std::int32_t(k);
    return n;
  };
  EXPECT_GT(mpi::allreduceSum(outOfPlace(gridOrder())), 50) << "shuffled: not in cell order";
  std::vector<Vec3> before;
  for (std::size_t i = 0; i < sim.particles().localCount(); ++i) {
    before.push_back(sim.particles()[i].position);
  }
  sim.step();
  std::int64_t moved = 0;  // (compared as sets: the order changed)
  for (std::size_t i = 0; i < sim.particles().localCount(); ++i) {
    moved += std::find(before.begin(), before.end(), sim.particles()[i].position) == before.end();
  }
  ASSERT_EQ(mpi::allreduceSum(moved), 0) << "the scene should not move";
  EXPECT_EQ(mpi::allreduceSum(outOfPlace(gridOrder())), 0) << "after the step's sort";
  EXPECT_GT(mpi::allreduceSum(sim.sorts()), 0);
}

}  // namespace
}  // namespace polydem::sim
