// [[joint]] in scene files: units as a rock engineer writes them, references from a rock mass's
// planes and joint sets, the joint planes every block's faces lie on, and every mistake an
// InputError at the line marked "# <-".
#include <gtest/gtest.h>

#include "scene_test_support.h"

namespace polydem::scene {
namespace {

using namespace scene_test;

const std::string kJoints = R"(
[[joint]]
name = "bedding"
law = "coulomb"
jkn = "10 GPa/m"
jks = "5e9 Pa/m"
friction_angle = 25
cohesion = "50 kPa"
tensile_strength = "0.1 MPa"

[[joint]]
name = "fault"
jkn = 1e9
jks = 1e9
friction_angle = "0.5 rad"
)";

const std::string kMass = R"(
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
name = "B"
dip = 20
dip_direction = 90
spacing = "1.5 m"
joint = "bedding"

[[rock_mass.joint_set]]
name = "J"
dip = 80
dip_direction = 0
spacing = "2 m"
)";

std::string scene(const std::string& joints = kJoints, const std::string& mass = kMass) {
  return kBase + joints + mass;
}

TEST(SceneJoints, PropertiesInEngineersUnits) {
  const setup::Setup s = parseScene(scene(), "test.toml");
  ASSERT_EQ(s.joints.size(), 2u);
  const setup::JointSpec& b = s.joints[0];
  EXPECT_EQ(b.name, "bedding");
  EXPECT_STREQ(b.lawName(), "coulomb");
  EXPECT_EQ(b.value("jkn"), 1e10);
  EXPECT_EQ(b.value("jks"), 5e9);
  EXPECT_EQ(b.value("friction_angle"), 25.0);
  EXPECT_EQ(b.value("cohesion"), 5e4);
  EXPECT_EQ(b.value("tensile_strength"), 1e5);
  EXPECT_NEAR(s.joints[1].value("friction_angle"), 0.5 * 180.0 / 3.141592653589793, 1e-12);
  EXPECT_EQ(s.joints[1].value("cohesion"), 0.0);
  EXPECT_EQ(s.joints[1].value("tensile_strength"), 0.0);
}

TEST(SceneJoints, PlanesTakeTheirJointAndFacesTheirPlane) {
  const setup::Setup s = parseScene(scene(), "test.toml");
  ASSERT_EQ(s.rock_masses.size(), 1u);
  const auto& names = s.rock_masses[0].plane_names;
  ASSERT_EQ(s.joint_planes.size(), names.size());
  int bedding = 0, unnamed = 0;
  for (std::size_t k = 0; k < names.size(); ++k) {
    const setup::JointPlaneSpec& p = s.joint_planes[k];
    EXPECT_EQ(p.name, "slope/" + names[k]);
    if (names[k] == "base") EXPECT_EQ(p.joint, 1);
    if (names[k].rfind("B#", 0) == 0) {
      EXPECT_EQ(p.joint, 0) << names[k];
      ++bedding;
    }
    if (names[k].rfind("J#", 0) == 0) {
      EXPECT_EQ(p.joint, -1) << names[k];
      ++unnamed;
    }
  }
  EXPECT_GE(bedding, 2);
  EXPECT_GE(unnamed, 1);
  // Every block has faces on planes (the region's own faces are on none), the blocks on the base
  // and the fixed one below it a face on the base, and each face plane listed holds three of the
  // block's corners.
  const std::size_t first = s.shapes.size() - static_cast<std::size_t>(s.rock_masses[0].blocks);
  int on_base = 0;
  for (std::size_t i = first; i < s.shapes.size(); ++i) {
    const setup::ShapeSpec& shape = s.shapes[i];
    EXPECT_FALSE(shape.face_planes.empty()) << shape.name;
    for (const setup::FacePlane& f : shape.face_planes) {
      on_base += names[static_cast<std::size_t>(f.plane)] == "base";
      int on = 0;
      for (const Vec3& v : shape.vertices) on += std::abs(f.normal.dot(v) - f.offset) < 1e-9;
      EXPECT_GE(on, 3) << shape.name << " plane " << f.plane;
    }
  }
  EXPECT_GE(on_base, 3);
}

TEST(SceneJoints, Mistakes) {
  expectError(scene(replaced(kJoints, "cohesion = \"50 kPa\"", "cohesion = \"50 kN\"  # <-")),
              {"[[joint]] 'bedding'", "cohesion", "pressure (Pa)"});
  expectError(scene(replaced(kJoints, "jkn = \"10 GPa/m\"", "jkn = \"10 GN/m\"  # <-")),
              {"jkn", "Pa/m"});
  expectError(scene(replaced(kJoints, "jks = 1e9\n", "jks = 0  # <-\n")), {"jks"});
  expectError(scene(replaced(kJoints, "law = \"coulomb\"", "law = \"barton\"  # <-")),
              {"law", "coulomb"});
  expectError(scene(replaced(kJoints, "friction_angle = 25", "friction_angle = 95  # <-")),
              {"friction_angle"});
  expectError(scene(kJoints + "\n[[joint]]\nname = \"bedding\"  # <-\njkn = 1\njks = 1\n"
                              "friction_angle = 1\n"),
              {"joint 'bedding' is already defined"});
  expectError(scene(replaced(kJoints, "tensile_strength = \"0.1 MPa\"",
                             "tensile_strength = \"0.1 MPa\"\nspacing = 1  # <-")),
              {"spacing"});
  expectError(scene(kJoints, replaced(kMass, "joint = \"bedding\"", "joint = \"beding\"  # <-")),
              {"no [[joint]] is named 'beding'"});
  expectError(scene(kJoints, replaced(kMass, "joint = \"fault\"", "joint = \"none\"  # <-")),
              {"[[plane]] 'base'", "no [[joint]] is named 'none'"});
}

// Each law's own parameters, read from its declaration (dynamics/joint_law.h): units, defaults,
// ranges, and the keys of one law refused on another.
const std::string kLaws = R"(
[[joint]]
name = "bedding"
law = "coulomb-residual"
jkn = "10 GPa/m"
jks = "5 GPa/m"
friction_angle = 35
cohesion = "50 kPa"

[[joint]]
name = "fault"
law = "barton-bandis"
jkn = "1 GPa/m"
jks = "0.5 GPa/m"
jrc = 12
jcs = "80 MPa"
residual_friction_angle = 28
field_length = "2 m"
)";

TEST(SceneJoints, EachLawItsParameters) {
  const setup::Setup s = parseScene(scene(kLaws), "test.toml");
  ASSERT_EQ(s.joints.size(), 2u);
  const setup::JointSpec& r = s.joints[0];
  EXPECT_STREQ(r.lawName(), "coulomb-residual");
  EXPECT_EQ(r.value("cohesion"), 5e4);
  EXPECT_EQ(r.value("tensile_strength"), 0.0);
  EXPECT_EQ(r.value("residual_friction_angle"), 35.0);  // default: friction_angle
  const setup::JointSpec& b = s.joints[1];
  EXPECT_STREQ(b.lawName(), "barton-bandis");
  EXPECT_EQ(b.value("jrc"), 12.0);
  EXPECT_EQ(b.value("jcs"), 8e7);
  EXPECT_EQ(b.value("residual_friction_angle"), 28.0);
  EXPECT_EQ(b.value("lab_length"), 0.1);  // default
  EXPECT_EQ(b.value("field_length"), 2.0);
  EXPECT_EQ(b.value("dilation"), 0.0);
  EXPECT_THROW(b.value("cohesion"), Error);
  const setup::Setup d =
      parseScene(scene(replaced(kLaws, "field_length = \"2 m\"", "dilation = true")), "test.toml");
  EXPECT_EQ(d.joints[1].value("dilation"), 1.0);
  EXPECT_EQ(d.joints[1].value("field_length"), 0.0);
}

TEST(SceneJoints, LawMistakes) {
  expectError(scene(replaced(kLaws, "jrc = 12", "jrc = 25  # <-")),
              {"[[joint]] 'fault'", "jrc", "[0, 20]", "barton-bandis"});
  expectError(scene(replaced(replaced(kLaws, "jcs = \"80 MPa\"\n", ""),
                             "[[joint]]\nname = \"fault\"", "[[joint]]  # <-\nname = \"fault\"")),
              {"[[joint]] 'fault'", "jcs"});
  expectError(scene(replaced(kLaws, "jcs = \"80 MPa\"", "jcs = \"80 MN\"  # <-")),
              {"jcs", "pressure (Pa)"});
  expectError(scene(replaced(kLaws, "jrc = 12", "jrc = 12\ncohesion = 1  # <-")),
              {"[[joint]] 'fault'", "cohesion"});
  expectError(
      scene(replaced(kLaws, "cohesion = \"50 kPa\"", "cohesion = \"50 kPa\"\njrc = 3  # <-")),
      {"[[joint]] 'bedding'", "jrc"});
  expectError(scene(replaced(kLaws, "friction_angle = 35",
                             "friction_angle = 35\nresidual_friction_angle = 90  # <-")),
              {"residual_friction_angle", "[0, 90)"});
  expectError(scene(replaced(kLaws, "field_length = \"2 m\"", "dilation = 1  # <-")),
              {"dilation", "true or false"});
}

}  // namespace
}  // namespace polydem::scene
