// Once warm, a step of a dense pack on one rank allocates nothing (DEVELOPING.md, "Hot paths"):
// the broad phase, the contact phase, the kernels' scratch, the sub-contact
// builder and law, the histories and the exchange reuse their buffers. Warm: 20 steps, after which
// the buffers that grow to the largest polygon seen have grown. Counted with the replaced global
// operator new. (On several ranks the exchange allocates the messages it receives.)
#include <gtest/gtest.h>

#include "common/allocation_counter.h"
#include "generators/pile_scene.h"
#include "polydem/core/logging.h"
#include "polydem/sim/simulation.h"

namespace polydem::sim {
namespace {

// Allocations of `steps` steps after `warmup` steps of a dense pack of `particles` cubes, whose
// storage is sorted into cell order every `sort_every` steps (0: never).
long allocationsPerSteps(std::int64_t particles, const std::string& model, int warmup, int steps,
                         std::int64_t sort_every = 0) {
  PileOptions o;
  o.particles = particles;
  o.shapes = "cubes";
  o.gap = -0.001;  // every face in contact from the first step
  o.layers = 4;
  setup::Setup scene = makePileScene(o);
  scene.contact_model = model;
  scene.domain.sort_every = sort_every;
  Simulation sim(scene, MPI_COMM_WORLD);
  for (int i = 0; i < warmup; ++i) sim.step();
  const long before = polydem::testing::allocationCount();
  for (int i = 0; i < steps; ++i) sim.step();
  return polydem::testing::allocationCount() - before;
}

TEST(StepAllocations, NoneOnceWarm) {
  log::setLevel(log::Level::kWarning);
  for (const std::string model : {"sub-contacts", "point"}) {
    const long small = allocationsPerSteps(64, model, 20, 5);
    const long large = allocationsPerSteps(400, model, 20, 5);
    EXPECT_EQ(small, 0) << model << ": allocations in 5 warm steps of 64 cubes";
    EXPECT_EQ(large, 0) << model << ": allocations in 5 warm steps of 400 cubes";
  }
}

TEST(StepAllocations, NoneWhenSortingEveryStep) {
  log::setLevel(log::Level::kWarning);
  EXPECT_EQ(allocationsPerSteps(400, "sub-contacts", 20, 5, 1), 0)
      << "allocations in 5 warm steps of 400 cubes, each with a sort into cell order";
}

}  // namespace
}  // namespace polydem::sim
