// Once warm, a search allocates nothing: the broad phase runs every step on every rank.
#include <gtest/gtest.h>

#include "broadphase/scenes.h"
#include "common/allocation_counter.h"
#include "polydem/broadphase/broad_phase.h"

namespace polydem::broadphase {
namespace {

TEST(BroadPhaseAllocations, NoneOnceWarm) {
  testing::Scene s = testing::randomScene(
      {.n = 5000, .size_ratio = 30.0, .solid_fraction = 0.3, .inactive_fraction = 0.2});
  s.add(Vec3(0, 0, -500.0), 500.0);  // a huge boundary body: a level of its own
  s.finish(1);
  for (const std::string name : {"multilevel", "nbs"}) {
    auto bp = makeBroadPhase(name);
    std::vector<CandidatePair> out;
    bp->findPairs(s.view(), 0.01, out);  // warm up
    const std::size_t pairs = out.size();
    out.reserve(2 * pairs);  // the caller's buffer: room for a few more pairs
    // Particles move a little: same buffers suffice.
    for (auto& c : s.centers) c.x() += 1e-3;
    const long before = polydem::testing::allocationCount();
    bp->findPairs(s.view(), 0.01, out);
    bp->findPairs(s.view(), 0.01, out);
    EXPECT_EQ(polydem::testing::allocationCount() - before, 0) << name;
    EXPECT_GT(pairs, 0u);
  }
}

}  // namespace
}  // namespace polydem::broadphase
