// [[rock_mass]] in scene files: blocks become shapes and particles in file order, fixed where a
// plane says so, and every mistake is an InputError at the line marked "# <-".
#include <gtest/gtest.h>

#include "polydem/geometry/convex_polyhedron.h"
#include "scene_test_support.h"

namespace polydem::scene {
namespace {

using namespace scene_test;

const std::string kRockMass = R"(
[[rock_mass]]
name = "slope"
material = "rock"
fixed_material = "bedrock"
min_volume = "0.01 m^3"
region = { type = "box", min = [0, 0, 0], max = [6, 4, 3] }

[[rock_mass.joint_set]]
name = "J1"
dip = 80
dip_direction = 90
spacing = "1.5 m"
offset = "0.2 m"

[[rock_mass.joint_set]]
name = "J2"
dip = 10
dip_direction = 270
spacing = 1

[[rock_mass.plane]]
name = "base"
dip = 30
dip_direction = 90
point = [3, 2, 1]
fixed = "below"
)";

std::string sceneWithRockMass() {
  return replaced(kBase, "kn = 1e9\n",
                  "kn = 1e9\n\n[[material]]\nname = \"bedrock\"\n"
                  "density = 2500\nkn = 1e9\n") +
         kRockMass +
         "\n[[particle]]\nlabel = \"after\"\nshape = \"cube\"\nmaterial = \"rock\"\n"
         "position = [20, 0, 0]\n";
}

double volumeOf(const setup::ShapeSpec& s) {
  return geometry::ConvexPolyhedron::fromPoints(s.vertices).volume();
}

TEST(SceneRockMass, BlocksBecomeParticlesInFileOrder) {
  const setup::Setup scene = parseScene(sceneWithRockMass(), "test.toml");
  ASSERT_EQ(scene.rock_masses.size(), 1u);
  const setup::RockMassInfo& info = scene.rock_masses[0];
  EXPECT_EQ(info.name, "slope");
  EXPECT_EQ(info.first_uid, 2u);  // after particle "a"
  EXPECT_GT(info.blocks, 10);
  EXPECT_EQ(info.report.free_blocks + info.report.fixed_blocks, info.blocks);
  EXPECT_EQ(info.report.fixed_blocks, 1);  // joints cut the free mass only
  ASSERT_EQ(scene.particles.size(), static_cast<std::size_t>(info.blocks) + 2);
  EXPECT_EQ(scene.particles.back().label, "after");
  EXPECT_EQ(scene.particles.back().uid, static_cast<Uid>(info.blocks) + 2);
  double volume = 0.0;
  for (int i = 0; i < info.blocks; ++i) {
    const setup::ParticleSpec& p = scene.particles[1 + i];
    EXPECT_EQ(p.uid, info.first_uid + static_cast<Uid>(i));
    EXPECT_EQ(p.label, "slope_" + std::to_string(i));
    EXPECT_EQ(p.material, p.fixed ? 1 : 0);
    EXPECT_EQ(scene.shapes[p.shape].name, "slope#" + std::to_string(i));
    EXPECT_TRUE(p.position.isZero());  // the vertices are where the block is
    volume += volumeOf(scene.shapes[p.shape]);
  }
  EXPECT_NEAR(volume, 72.0, 1e-12 * 72.0);
  EXPECT_EQ(info.plane_names.front(), "base");
}

TEST(SceneRockMass, ProfileRegionAndLabelPrefix) {
  const std::string text =
      replaced(kBase, "[[particle]]\nlabel = \"a\"\nshape = \"cube\"\nmaterial = \"rock\"\n", "") +
      R"(
[[rock_mass]]
name = "cut"
material = "rock"
label_prefix = "b"
region = { type = "profile", profile = [[0, 0], [20, 0], [20, 12], [12, 12], [4, 4], [0, 4]], y = ["-3 m", "3 m"] }
[[rock_mass.joint_set]]
name = "vertical"
dip = 90
dip_direction = 90
spacing = 4
)";
  const setup::Setup scene = parseScene(text, "test.toml");
  ASSERT_EQ(scene.rock_masses.size(), 1u);
  double volume = 0.0;
  for (const setup::ShapeSpec& s : scene.shapes) {
    if (s.name.rfind("cut#", 0) == 0) volume += volumeOf(s);
  }
  const double area = 20.0 * 12.0 - 0.5 * 8.0 * 8.0 - 4.0 * 8.0;
  EXPECT_NEAR(volume, area * 6.0, 1e-12 * area * 6.0);
  EXPECT_EQ(scene.particles.front().label, "b_0");
}

TEST(SceneRockMassErrors, EveryMistakeHasItsLine) {
  const std::string base = sceneWithRockMass();
  expectError(replaced(base, "spacing = 1\n", "spacing = 1\nspaceing = 2  # <-\n"),
              {"[[rock_mass]] 'slope' [[joint_set]] 'J2': unknown key 'spaceing'"});
  expectError(replaced(base, "dip = 10\n", "dip = 95  # <-\n"), {"[[joint_set]] 'J2' dip", "90"});
  expectError(replaced(base, "spacing = 1\n", "spacing = -1  # <-\n"),
              {"[[joint_set]] 'J2' spacing", "> 0"});
  expectError(replaced(base, "spacing = \"1.5 m\"\n", "spacing = \"1.5 m^2\"  # <-\n"),
              {"[[joint_set]] 'J1' spacing", "length"});
  expectError(replaced(base, "min_volume = \"0.01 m^3\"", "min_volume = \"0.01 m\"  # <-"),
              {"min_volume", "volume"});
  expectError(replaced(base, "material = \"rock\"\nfixed_material",
                       "material = \"granite\"  # <-\nfixed_material"),
              {"[[rock_mass]] 'slope' material", "no [[material]] is named 'granite'"});
  expectError(replaced(replaced(base, "max = [6, 4, 3] }", "max = [6, 4, 3] }  # <-"),
                       "type = \"box\"", "type = \"sphere\""),
              {"region type", "'sphere'"});
  expectError(replaced(base, "fixed = \"below\"", "fixed = \"below\"\nremove = \"below\"  # <-"),
              {"[[plane]] 'base' remove", "both fixed and removed"});
  expectError(replaced(base, "name = \"J2\"", "name = \"J1\"  # <-"), {"'J1' is already used"});
  expectError(replaced(replaced(base, "point = [3, 2, 1]\n", ""), "[[rock_mass.plane]]",
                       "[[rock_mass.plane]]  # <-"),
              {"missing required key 'point'"});
  expectError(replaced(base, "max = [6, 4, 3] }", "max = [6, 4, -3] }  # <-"),
              {"region max", "must exceed min"});
  expectError(replaced(base, "[[rock_mass.plane]]", "[rock_mass.plane]  # <-"),
              {"'slope' plane", "array of tables"});
  // A profile whose edges cross cannot be cut: the region's line.
  expectError(replaced(base, "region = { type = \"box\", min = [0, 0, 0], max = [6, 4, 3] }",
                       "region = { type = \"profile\", profile = [[0, 0], [6, 0], [0, 4], [2, "
                       "5]], y = [0, 1] }  # <-"),
              {"invalid region", "cross"});
  // Two rock masses of one name.
  expectError(base + replaced(kRockMass, "name = \"slope\"", "name = \"slope\"  # <-"),
              {"rock mass 'slope' is already defined"});
  // A [[shape]] of a block's name ("<rock mass>#<index>").
  expectError(replaced(base, "name = \"slope\"", "name = \"slope\"  # <-") +
                  "\n[[shape]]\nname = \"slope#3\"\ntype = \"box\"\nsize = [1, 1, 1]\n",
              {"its block shape 'slope#3' clashes with the [[shape]] at line"});
}

// Descriptions beyond the limits are refused before any cutting, at the line of the table
// that says too much, with the numbers and what to change.
TEST(SceneRockMassErrors, LimitsAreRefusedWithTheirLine) {
  const std::string base = sceneWithRockMass();
  // 1 um joints: the set's own line, its spacing and plane count (not its origin).
  expectError(replaced(replaced(base, "spacing = 1\n", "spacing = \"1 um\"\n"),
                       "[[rock_mass.joint_set]]\nname = \"J2\"",
                       "[[rock_mass.joint_set]]  # <-\nname = \"J2\""),
              {"[[joint_set]] 'J2': spacing 1e-06 m gives about", "planes across the region",
               "is the spacing in metres?"});
  // Two sets of 8 mm in a 30 m box: the [[rock_mass]] line, the estimate and both sets.
  std::string fine = replaced(base, "max = [6, 4, 3] }", "max = [30, 30, 30] }");
  fine = replaced(fine, "spacing = \"1.5 m\"", "spacing = \"8 mm\"");
  fine = replaced(fine, "spacing = 1\n", "spacing = \"8 mm\"\n");
  fine = replaced(fine, "[[rock_mass]]\n", "[[rock_mass]]  # <-\n");
  expectError(fine, {"cannot cut the rock mass", "blocks ('base' 1 plane, 'J1'", "0.008 m",
                     "more than the limit of 1e+06", "increase the joint sets' spacings"});
}

// max_blocks sets the limit the estimate is held to: lowered below the mass's blocks it refuses
// the cut at the [[rock_mass]] line, raised it lets the same mass through unchanged.
TEST(SceneRockMassErrors, MaxBlocksSetsTheLimit) {
  const std::string marked =
      replaced(sceneWithRockMass(), "[[rock_mass]]\n", "[[rock_mass]]  # <-\nmax_blocks = 5\n");
  expectError(marked, {"cannot cut the rock mass", "more than the limit of 5", "raise max_blocks"});
  const std::string raised =
      replaced(sceneWithRockMass(), "[[rock_mass]]\n", "[[rock_mass]]\nmax_blocks = 2e6\n");
  EXPECT_EQ(parseScene(raised, "test.toml").rock_masses.at(0).blocks,
            parseScene(sceneWithRockMass(), "test.toml").rock_masses.at(0).blocks);
  expectError(
      replaced(sceneWithRockMass(), "[[rock_mass]]\n", "[[rock_mass]]\nmax_blocks = 0  # <-\n"),
      {"max_blocks"});
}

TEST(SceneRockMassErrors, RemovingEverythingIsAnError) {
  const std::string text =
      replaced(sceneWithRockMass(), "[[rock_mass]]\n", "[[rock_mass]]  # <-\n");
  expectError(replaced(text, "fixed = \"below\"",
                       "remove = \"below\"\n[[rock_mass.plane]]\n"
                       "name = \"top\"\ndip = 0\ndip_direction = 0\n"
                       "point = [0, 0, -5]\nremove = \"above\""),
              {"no block is left"});
}

}  // namespace
}  // namespace polydem::scene
