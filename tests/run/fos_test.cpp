// Factor of safety by strength reduction (sim/fos.h) against the analytical answers: a block on
// an incline, F = tan(phi) / tan(theta), and Hoek and Bray's symmetric wedge,
// F = tan(phi) / (tan(psi) sin(xi / 2)), each within 2 %; plus the strength reduction itself.
//
// With sub-contacts (the default) every kernel is within 2 %. Known failures are asserted to
// fail, with the reason, so that a fix shows up here (the README says the same): with
// contact_model = "point", IPM's point stays at the centre of a face contact while the block
// tilts within the overlap, so the contact has no rotational stiffness; a block on the incline
// rocks and creeps down at a friction angle above the incline's, and fcp's plane lets the wedge
// creep.
#include <gtest/gtest.h>

#include <cmath>

#include "polydem/core/error.h"
#include "polydem/core/logging.h"
#include "polydem/run/fos.h"
#include "polydem/scene/scene_reader.h"

namespace polydem::sim {
namespace {

const std::string kExamples = std::string(POLYDEM_SCENES_DIR) + "/examples/";

// The factor of safety found, or NaN when the search did not bracket it (the note says why).
double fosOf(const std::string& file, const std::string& kernel, const std::string& model,
             std::string& note) {
  log::setLevel(log::Level::kWarning);
  io::Scene scene = io::readScene(kExamples + file);
  scene.kernel = kernel;
  scene.contact_model = model;
  const FosResult r = findFactorOfSafety(scene, fosCriterion(scene), 1, MPI_COMM_WORLD);
  note = r.note;
  if (!r.factor()) return NAN;
  EXPECT_LE(*r.failed - *r.stable, scene.fos.resolution);
  return *r.factor();
}

struct Case {
  const char* file;
  const char* kernel;
  double analytical;
  const char* known_failure = nullptr;  // why this kernel misses by more than 2 %
  const char* contact_model = "sub-contacts";
};

constexpr const char* kRocking =
    "single-point contact at the face centre (IPM): no rotational stiffness, the block rocks and "
    "creeps at friction angles up to 0.9 deg above the incline's (F about 3 % low)";
constexpr const char* kFcpWedge =
    "fcp's plane on the two inclined walls: the wedge creeps even at F = 0.5";

const double kIncline = std::tan(degToRad(40.0)) / std::tan(degToRad(30.0));
const double kWedge = std::tan(degToRad(30.0)) / (std::tan(degToRad(30.0)) * std::sin(kPi / 4));

class AnalyticalFos : public ::testing::TestWithParam<Case> {};

TEST_P(AnalyticalFos, WithinTwoPercent) {
  const Case& c = GetParam();
  std::string note;
  const double f = fosOf(c.file, c.kernel, c.contact_model, note);
  const double error = std::abs(f - c.analytical) / c.analytical;  // NaN when not bracketed
  if (c.known_failure) {
    EXPECT_FALSE(error <= 0.02) << c.file << " with " << c.kernel << ": F = " << f
                                << " now within 2 % of " << c.analytical
                                << "; listed as a known failure (" << c.known_failure << ")";
  } else {
    EXPECT_LE(error, 0.02) << c.file << " with " << c.kernel << ": F = " << f << ", analytical "
                           << c.analytical << " " << note;
  }
}

INSTANTIATE_TEST_SUITE_P(
    Scenes, AnalyticalFos,
    ::testing::Values(
        Case{"fos-incline.toml", "gjk-epa-ipm", kIncline},
        Case{"fos-incline.toml", "fcp-ipm", kIncline}, Case{"fos-incline.toml", "lp", kIncline},
        Case{"fos-incline.toml", "distance-potential", kIncline},
        Case{"fos-wedge.toml", "gjk-epa-ipm", kWedge}, Case{"fos-wedge.toml", "fcp-ipm", kWedge},
        Case{"fos-wedge.toml", "lp", kWedge}, Case{"fos-wedge.toml", "distance-potential", kWedge},
        Case{"fos-wedge.toml", "fcp", kWedge},
        Case{"fos-incline.toml", "gjk-epa-ipm", kIncline, kRocking, "point"},
        Case{"fos-incline.toml", "fcp-ipm", kIncline, kRocking, "point"},
        Case{"fos-wedge.toml", "fcp", kWedge, kFcpWedge, "point"}),
    [](const ::testing::TestParamInfo<Case>& param_info) {
      std::string name = std::string(param_info.param.file) + "_" + param_info.param.kernel + "_" +
                         param_info.param.contact_model;
      for (char& ch : name) ch = std::isalnum(static_cast<unsigned char>(ch)) ? ch : '_';
      return name;
    });

TEST(StrengthReduction, DividesTanPhiAndCohesionOfTheChosenPairs) {
  io::Scene scene = io::readScene(kExamples + "fos-incline.toml");
  particles::Material soft = scene.materials[0];
  soft.name = "clay";
  soft.friction_angle = 20;
  soft.cohesion = 300;
  scene.materials.push_back(soft);
  scene.fos.interactions = {{0, 1}};
  const io::Scene reduced = reduceStrength(scene, 2.0);
  ASSERT_EQ(reduced.interactions.size(), 1u);
  const auto& p = reduced.interactions[0].properties;
  // The pair takes the lower friction and cohesion of the two materials, then is reduced.
  EXPECT_DOUBLE_EQ(std::tan(degToRad(p.friction_angle)), std::tan(degToRad(20.0)) / 2.0);
  EXPECT_DOUBLE_EQ(p.cohesion, 0.0);
  EXPECT_DOUBLE_EQ(p.kn, scene.materials[0].kn);
  EXPECT_EQ(reducedPairs(scene).size(), 1u);
  scene.fos.interactions.clear();  // every pair: (0,0), (0,1), (1,1)
  const io::Scene all = reduceStrength(scene, 4.0);
  ASSERT_EQ(all.interactions.size(), 3u);
  for (const auto& i : all.interactions) {
    if (i.a == 1 && i.b == 1) {
      EXPECT_DOUBLE_EQ(i.properties.cohesion, 75.0);
    }
  }
  EXPECT_THROW(reduceStrength(scene, 0.0), Error);
}

TEST(FosCriterion, DefaultsAndMissingMaxTime) {
  io::Scene scene = io::readScene(kExamples + "fos-incline.toml");
  scene.fos.settle_time.reset();
  scene.fos.displacement_limit.reset();
  const FosCriterion c = fosCriterion(scene);
  EXPECT_DOUBLE_EQ(c.settle_time, 0.5);           // max_time / 4
  EXPECT_NEAR(c.displacement_limit, 0.1, 1e-12);  // 0.1 x the unit cube
  scene.fos.max_time.reset();
  try {
    fosCriterion(scene);
    FAIL() << "no error without max_time";
  } catch (const InputError& e) {
    EXPECT_GT(e.line(), 0);
    EXPECT_NE(std::string(e.what()).find("max_time"), std::string::npos);
  }
}

}  // namespace
}  // namespace polydem::sim
