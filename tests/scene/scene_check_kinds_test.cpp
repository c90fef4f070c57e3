// [[check]] against its kind's declared parameters (scene/check_kinds.h): a
// misspelt or undeclared key, a missing required one, a value out of its range or of the wrong
// unit, an unknown label, all are errors at the line of the key (marked "# <-"), never a
// silent default.
#include <gtest/gtest.h>

#include <fstream>
#include <iterator>

#include "polydem/core/strings.h"
#include "polydem/scene/check_kinds.h"
#include "scene_test_support.h"

namespace polydem::scene {
namespace {

using namespace scene_test;

// kBase plus a sliding_block check; `extra` lines go at its end.
std::string sliding(const std::string& extra = "") {
  return kBase +
         "[[check]]\nname = \"slide\"\nkind = \"sliding_block\"\nexpected = 0.01\n"
         "compare = \"max\"\nparticle = \"a\"\ntheta = 30\nmu = 0.4\nu0 = \"6 m/s\"\n"
         "direction = [0.866025403784, 0, 0.5]\n" +
         extra;
}

TEST(SceneCheckKinds, AValidCheckReadsItsParameters) {
  const setup::Setup s =
      parseScene(sliding("g = \"9.81 m/s^2\"\nquantity = \"velocity\"\n"), "t.toml");
  ASSERT_EQ(s.checks.size(), 1u);
  const setup::CheckSpec& c = s.checks[0];
  EXPECT_EQ(c.numbers.at("theta"), std::vector<double>{30.0});
  EXPECT_EQ(c.numbers.at("mu"), std::vector<double>{0.4});
  EXPECT_EQ(c.numbers.at("u0"), std::vector<double>{6.0});
  EXPECT_EQ(c.numbers.at("g"), std::vector<double>{9.81});
  EXPECT_NEAR(c.numbers.at("direction")[0], 0.866025403784, 1e-12);
  EXPECT_EQ(c.strings.at("quantity"), "velocity");
  EXPECT_EQ(c.strings.at("particle"), "a");
}

TEST(SceneCheckKinds, MisspeltKeysAreErrorsAtTheirLine) {
  expectError(sliding("tolerence = 0.1  # <-\n"),
              {"[[check]] 'slide': unknown key 'tolerence'", "did you mean 'tolerance'"});
  expectError(sliding("compre = \"rel\"  # <-\n"), {"unknown key 'compre'", "'compare'"});
  expectError(sliding("thetta = 20  # <-\n"), {"unknown key 'thetta'", "did you mean 'theta'"});
  // A parameter of another kind is unknown for this one.
  expectError(kBase +
                  "[[check]]\nname = \"t\"\nkind = \"separation_time\"\nexpected = 1\n"
                  "particle = \"a\"\naxis = [0, 0, 1]  # <-\n",
              {"unknown key 'axis'", "known keys: name, kind"});
}

TEST(SceneCheckKinds, UnknownKindAtItsLine) {
  expectError(kBase + "[[check]]\nname = \"e\"\nkind = \"energy\"  # <-\nexpected = 1\n",
              {"'energy' is not a check kind", "known: displacement, rotation"});
}

TEST(SceneCheckKinds, ValuesOutOfRange) {
  expectError(replaced(sliding(), "mu = 0.4", "mu = -1e308  # <-"),
              {"[[check]] 'slide' mu: must be >= 0, got -1e+308"});
  expectError(replaced(sliding(), "theta = 30", "theta = 95  # <-"),
              {"theta: must be [0, 90], got 95"});
  expectError(replaced(sliding(), "u0 = \"6 m/s\"", "u0 = -1  # <-"), {"u0: must be >= 0"});
  expectError(sliding("g = 0  # <-\n"), {"g: must be > 0, got 0"});
  expectError(
      replaced(sliding(), "direction = [0.866025403784, 0, 0.5]", "direction = [0, 0, 0]  # <-"),
      {"direction: must not be zero"});
  expectError(sliding("quantity = \"speed\"  # <-\n"),
              {"'speed' is not one of displacement, velocity"});
  expectError(sliding("tolerance = -1  # <-\n"), {"tolerance: must be >= 0"});
  // A wedge needs an inclined line.
  expectError(kBase +
                  "[[check]]\nname = \"w\"\nkind = \"wedge_slide\"\nexpected = 1\n"
                  "particle = \"a\"\ndirection = [1, 0, 0]\ntheta = 0  # <-\n",
              {"theta: must be (0, 90], got 0"});
}

TEST(SceneCheckKinds, UnitsOfTheValueAndParameters) {
  // A displacement is a length; a rotation an angle (stored in radians).
  expectError(kBase +
                  "[[check]]\nname = \"d\"\nkind = \"displacement\"\nparticle = \"a\"\n"
                  "expected = \"2 s\"  # <-\n",
              {"expected: expected a length (m), got '2 s'"});
  expectError(replaced(sliding(), "u0 = \"6 m/s\"", "u0 = \"6 m\"  # <-"),
              {"u0: expected a velocity"});
  const setup::Setup s = parseScene(kBase +
                                        "[[check]]\nname = \"r\"\nkind = \"rotation\"\n"
                                        "particle = \"a\"\nexpected = \"90 deg\"\n",
                                    "t.toml");
  EXPECT_NEAR(s.checks[0].expected, 1.5707963267948966, 1e-15);
}

TEST(SceneCheckKinds, ParticlesAndRequiredParameters) {
  expectError(replaced(sliding(), "particle = \"a\"", "particle = \"b\"  # <-"),
              {"particle: no particle is labelled 'b'"});
  expectError(replaced(sliding(), "particle = \"a\"", "particle = \"a, a\"  # <-"),
              {"particle: takes one particle label, got 'a, a'"});
  expectError(kBase +
                  "[[check]]\nname = \"d\"\nkind = \"displacement\"\nexpected = 1\n"
                  "particle = \"a,,a\"  # <-\n",
              {"has an empty label"});
  const std::string no_mu = replaced(sliding(), "mu = 0.4\n", "");
  expectError(replaced(no_mu, "[[check]]", "[[check]]  # <-"),
              {"[[check]] 'slide': missing required key 'mu'"});
  // A list of several labels where the kind takes several.
  const setup::Setup s = parseScene(kBase +
                                        "[[particle]]\nlabel = \"b\"\nshape = \"cube\"\n"
                                        "material = \"rock\"\nposition = [3, 0, 0]\n"
                                        "[[check]]\nname = \"d\"\nkind = \"displacement\"\n"
                                        "expected = 1\nparticle = \" a , b \"\n",
                                    "t.toml");
  EXPECT_EQ(s.checks[0].strings.at("particle"), "a,b");
}

TEST(SceneCheckKinds, HugeDirectionsAreNormalisedWithoutOverflow) {
  const setup::Setup s = parseScene(
      replaced(sliding(), "direction = [0.866025403784, 0, 0.5]", "direction = [1e300, 0, 1e300]"),
      "t.toml");
  const auto& d = s.checks[0].numbers.at("direction");
  EXPECT_NEAR(d[0], std::sqrt(0.5), 1e-15);
  EXPECT_NEAR(d[2], std::sqrt(0.5), 1e-15);
}

TEST(SceneCheckKinds, EveryKindDeclaresItsValueAndParameters) {
  // ... and docs/scene-format.md lists it.
  std::ifstream in(std::string(POLYDEM_SOURCE_DIR) + "/docs/scene-format.md");
  const std::string docs((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  ASSERT_FALSE(docs.empty());
  EXPECT_GE(checkKinds().size(), 12u);
  for (const auto& kind : checkKinds()) {
    EXPECT_NE(docs.find(cat("`", kind.name, "`")), std::string::npos) << kind.name;
    EXPECT_FALSE(kind.value_help.empty()) << kind.name;
    for (const auto& p : kind.params) {
      EXPECT_FALSE(p.help.empty()) << kind.name << " " << p.name;
      EXPECT_EQ(findCheckParam(kind, p.name), &p);
    }
  }
}

}  // namespace
}  // namespace polydem::scene
