// Values that are valid TOML but no valid scene, or that overflow: a quaternion
// or axis whose norm overflows, subnormal numbers, quantities that overflow in their stored unit,
// and particle grids too large for the memory of the machine, each an error at its line (or, for
// the rotations, read correctly).
#include <gtest/gtest.h>

#include "polydem/core/strings.h"
#include "scene_test_support.h"

namespace polydem::scene {
namespace {

using namespace scene_test;

TEST(SceneBadValues, RotationsWithHugeComponentsAreNormalised) {
  // [1e308, 1e308, 0, 0]: 90 degrees about x; its norm overflows to infinity.
  const setup::Setup s =
      parseScene(kBase + "rotation = { quaternion = [1e308, 1e308, 0, 0] }\n", "t");
  const Quat& q = s.particles[0].orientation;
  EXPECT_NEAR(q.w(), std::sqrt(0.5), 1e-15);
  EXPECT_NEAR(q.x(), std::sqrt(0.5), 1e-15);
  const setup::Setup a =
      parseScene(kBase + "rotation = { axis = [1e300, 0, 0], angle = 90 }\n", "t");
  EXPECT_NEAR(a.particles[0].orientation.x(), std::sqrt(0.5), 1e-15);
  expectError(kBase + "rotation = { quaternion = [0, 0, 0, 0] }  # <-\n", {"must not be zero"});
}

TEST(SceneBadValues, SubnormalNumbers) {
  expectError(replaced(kBase, "density = 2500", "density = 1e-310  # <-"),
              {"[[material]] 'rock' density: 1e-310 is below the smallest normal number"});
  expectError(replaced(kBase, "kn = 1e9", "kn = \"1e-310 N/m\"  # <-"),
              {"kn: '1e-310 N/m' is below the smallest normal number"});
  expectError(kBase + "position = [0, 4e-320, 0]  # <-\n", {"position[1]"});
  // Zero stays allowed.
  EXPECT_NO_THROW(parseScene(kBase + "position = [0, 0, 0]\n", "t"));
}

TEST(SceneBadValues, QuantitiesThatOverflowInTheirStoredUnit) {
  expectError(kBase + "rotation = { axis = [0, 0, 1], angle = \"1e307 rad\" }  # <-\n",
              {"overflows in an angle"});
}

TEST(SceneBadValues, GridsTooLargeForTheMemory) {
  expectError(kBase +
                  "[[particle_grid]]\nshape = \"cube\"\nmaterial = \"rock\"\n"
                  "spacing = 2\ncount = [1000, 1000, 1000]  # <-\n",
              {"count: the scene would have 1000000001 particles, which need about 1.5 TB",
               "of memory available on this machine"});
}

TEST(SceneBadValues, DomainValuesAtTheirLine) {
  const std::string box = "[domain]\nmin = [-5, -5, -5]\nmax = [5, 5, 5]\n";
  expectError(kBase + box + "blocks = [100000, 100000, 100000]  # <-\n",
              {"[domain] blocks: 1000000000000000 blocks exceed the limit of 2147483647"});
  expectError(kBase + box + "blocks = [2147483647, 1, 1]  # <-\n",
              {"blocks need about 550 GB, more than the"});
  expectError(kBase + "[domain]\nmin = [-1e308, -5, -5]\nmax = [1e308, 5, 5]  # <-\n",
              {"[domain] max: the box from min to max is too large: its extent overflows"});
  expectError(kBase + "[domain]\nmin = [-1e-305, -5, -5]\nmax = [1e-305, 5, 5]\n" +
                  "blocks = [100000, 1, 1]  # <-\n",
              {"make blocks of edge", "below the smallest normal number"});
  // The line kept for errors found later (the block count against the rank count).
  EXPECT_EQ(parseScene(kBase + box + "blocks = [2, 2, 1]\n", "t").domain.line,
            lineContaining(kBase + box + "blocks = [2, 2, 1]\n", "blocks ="));
}

}  // namespace
}  // namespace polydem::scene
