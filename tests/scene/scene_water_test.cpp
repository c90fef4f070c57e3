// [water] in scene files: a phreatic surface through more than three points (triangulated in
// plan, with a table of their heights), [[water.joint]] surfaces found by [[joint]], plane and
// joint set names, the global surface left out; every mistake an InputError at the line marked
// "# <-" (points at one place or on one line, a table row of the wrong width, an unknown joint,
// a joint given water twice or none).
#include <gtest/gtest.h>

#include "scene_test_support.h"

namespace polydem::scene {
namespace {

using namespace scene_test;

const std::string kMass = R"(
[[joint]]
name = "fault"
jkn = 1e9
jks = 1e9
friction_angle = 30

[[rock_mass]]
name = "slope"
material = "rock"
region = { type = "box", min = [0, 0, 0], max = [4, 4, 3] }

[[rock_mass.plane]]
name = "base"
dip = 0
dip_direction = 0
point = [0, 0, 1]
fixed = "below"
joint = "fault"

[[rock_mass.joint_set]]
name = "J"
dip = 80
dip_direction = 0
spacing = "2 m"
)";

std::string scene(const std::string& water) {
  return kBase + kMass + "\n[water]\n" + water;
}

TEST(SceneWater, SurfaceThroughFivePoints) {
  const setup::Setup s = parseScene(
      scene("points = [[0, 0, 1], [4, 0, 1.5], [4, 4, 2], [0, 4, 1], [2, 2, \"3 m\"]]\n"),
      "test.toml");
  ASSERT_TRUE(s.water.enabled);
  EXPECT_EQ(s.water.points.size(), 5u);
  EXPECT_EQ(s.water.triangles.size(), 4u);  // the centre joined to the four corners
  EXPECT_EQ(s.water.heights, (std::vector<std::vector<double>>{{1, 1.5, 2, 1, 3}}));
  EXPECT_FALSE(s.water.dry);
}

TEST(SceneWater, TableOfTheHeightsOfNPoints) {
  const setup::Setup s = parseScene(scene("points = [[0, 0], [4, 0], [4, 4], [0, 4]]\n"
                                          "table = [[0, 1, 1, 1, 1], [10, 2, 2, 3, 3]]\n"),
                                    "test.toml");
  EXPECT_EQ(s.water.triangles.size(), 2u);
  EXPECT_EQ(s.water.times, (std::vector<double>{0, 10}));
  EXPECT_EQ(s.water.heights[1], (std::vector<double>{2, 2, 3, 3}));
}

TEST(SceneWater, JointSurfacesByJointPlaneAndSetName) {
  const setup::Setup s = parseScene(scene("level = 2.5\n"
                                          "[[water.joint]]\njoint = \"fault\"\ndry = true\n"
                                          "[[water.joint]]\njoint = \"J\"\nlevel = \"1.5 m\"\n"),
                                    "test.toml");
  ASSERT_EQ(s.water.joints.size(), 2u);
  const auto& planes = s.joint_planes;
  auto names = [&](const setup::WaterJointSpec& j) {
    std::vector<std::string> out;
    for (const int k : j.planes) out.push_back(planes[static_cast<std::size_t>(k)].name);
    return out;
  };
  EXPECT_EQ(names(s.water.joints[0]), std::vector<std::string>{"slope/base"});
  EXPECT_TRUE(s.water.joints[0].surface.dry);
  const auto set = names(s.water.joints[1]);
  ASSERT_FALSE(set.empty());
  for (const auto& n : set) EXPECT_EQ(n.substr(0, 8), "slope/J#");
  EXPECT_EQ(s.water.joints[1].surface.heights, (std::vector<std::vector<double>>{{1.5}}));
  // A plane by its own name, and no global surface: water only on that joint.
  const setup::Setup t =
      parseScene(scene("[[water.joint]]\njoint = \"slope/base\"\nlevel = 2\n"), "test.toml");
  EXPECT_TRUE(t.water.dry);
  EXPECT_EQ(names(t.water.joints[0]), std::vector<std::string>{"slope/base"});
}

TEST(SceneWater, BadSurfacesAndJointsNameTheLine) {
  expectError(scene("points = [[0, 0, 1], [4, 0, 1], [4, 4, 2], [4, 0, 2]]  # <-\n"),
              {"test.toml", "[water] points", "points 2 and 4 lie at one place in plan"});
  expectError(scene("points = [[0, 0, 1], [1, 1, 1], [2, 2, 2], [3, 3, 2]]  # <-\n"),
              {"[water] points", "on one line in plan"});
  expectError(scene("points = [[0, 0], [4, 0], [4, 4], [0, 4]]\n"
                    "table = [[0, 1, 1, 1, 1],\n  [10, 2, 2, 3]]  # <-\n"),
              {"[water] table[1]", "[time, z1 .. z4]", "a row of 4"});
  expectError(scene("level = 1\n[[water.joint]]\njoint = \"crack\"  # <-\nlevel = 2\n"),
              {"[[water.joint]] #1 joint", "'crack'", "known: fault, slope/base"});
  expectError(scene("level = 1\n[[water.joint]]  # <-\njoint = \"fault\"\n"),
              {"[[water.joint]] #1", "level, points, table, or dry = true"});
  expectError(scene("level = 1\n[[water.joint]]\njoint = \"fault\"\ndry = false  # <-\n"),
              {"dry = true"});
  expectError(scene("level = 1\n[[water.joint]]\njoint = \"fault\"\nlevel = 2\n"
                    "[[water.joint]]\njoint = \"base\"  # <-\ndry = true\n"),
              {"slope/base already has", "line"});
  expectError(scene("[[water.joint]]\njoint = \"fault\"\nlevel = 2\ndry = true  # <-\n"),
              {"give the surface once"});
}

}  // namespace
}  // namespace polydem::scene
