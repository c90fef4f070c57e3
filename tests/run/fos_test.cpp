// Factor of safety by strength reduction (run/fos.h) against the analytical answers: a block on
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

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iterator>

#include "polydem/core/error.h"
#include "polydem/core/logging.h"
#include "polydem/dynamics/joint_law.h"
#include "polydem/run/fos.h"
#include "polydem/scene/scene_reader.h"

namespace polydem::sim {
namespace {

const std::string kExamples = std::string(POLYDEM_SCENES_DIR) + "/examples/";

// The factor of safety found, or NaN when the search did not bracket it (the note says why).
double fosOf(const std::string& file, const std::string& kernel, const std::string& model,
             std::string& note) {
  log::setLevel(log::Level::kWarning);
  setup::Setup scene = scene::readScene(kExamples + file);
  scene.kernel = kernel;
  scene.contact_model = model;
  const run::FosResult r =
      run::findFactorOfSafety(scene, run::fosCriterion(scene), 1, MPI_COMM_WORLD);
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
        // Single-point contact at the face centre (IPM) has no rotational stiffness: the block
        // rocks and creeps by a millionth of its size, which the criterion does not call failure.
        Case{"fos-incline.toml", "gjk-epa-ipm", kIncline, nullptr, "point"},
        Case{"fos-incline.toml", "fcp-ipm", kIncline, nullptr, "point"},
        Case{"fos-wedge.toml", "fcp", kWedge, kFcpWedge, "point"}),
    [](const ::testing::TestParamInfo<Case>& param_info) {
      std::string name = std::string(param_info.param.file) + "_" + param_info.param.kernel + "_" +
                         param_info.param.contact_model;
      for (char& ch : name) ch = std::isalnum(static_cast<unsigned char>(ch)) ? ch : '_';
      return name;
    });

TEST(StrengthReduction, DividesTanPhiAndCohesionOfTheChosenPairs) {
  setup::Setup scene = scene::readScene(kExamples + "fos-incline.toml");
  particles::Material soft = scene.materials[0];
  soft.name = "clay";
  soft.friction_angle = 20;
  soft.cohesion = 300;
  scene.materials.push_back(soft);
  scene.fos.interactions = {{0, 1}};
  const setup::Setup reduced = run::reduceStrength(scene, 2.0);
  ASSERT_EQ(reduced.interactions.size(), 1u);
  const auto& p = reduced.interactions[0].properties;
  // The pair takes the lower friction and cohesion of the two materials, then is reduced.
  EXPECT_DOUBLE_EQ(std::tan(degToRad(p.friction_angle)), std::tan(degToRad(20.0)) / 2.0);
  EXPECT_DOUBLE_EQ(p.cohesion, 0.0);
  EXPECT_DOUBLE_EQ(p.kn, scene.materials[0].kn);
  EXPECT_EQ(run::reducedPairs(scene).size(), 1u);
  // Two free clay blocks: every pair, (0,0), (0,1), (1,1), has a contact that can use it.
  for (int k = 0; k < 2; ++k) {
    setup::ParticleSpec clay = scene.particles[1];
    clay.material = 1;
    clay.uid = static_cast<Uid>(scene.particles.size() + 1);
    clay.position.y() += 2.0 * (k + 1);
    scene.particles.push_back(clay);
  }
  scene.fos.interactions.clear();
  const setup::Setup all = run::reduceStrength(scene, 4.0);
  ASSERT_EQ(all.interactions.size(), 3u);
  for (const auto& i : all.interactions) {
    if (i.a == 1 && i.b == 1) {
      EXPECT_DOUBLE_EQ(i.properties.cohesion, 75.0);
    }
  }
  EXPECT_THROW(run::reduceStrength(scene, 0.0), Error);
}

TEST(StrengthReduction, NeverReducesOrListsAPairOnlyFixedBodiesShare) {
  // The incline becomes "bedrock": bedrock/bedrock only ever meets itself fixed.
  setup::Setup scene = scene::readScene(kExamples + "fos-incline.toml");
  particles::Material bedrock = scene.materials[0];
  bedrock.name = "bedrock";
  scene.materials.push_back(bedrock);
  scene.particles[0].material = 1;
  setup::ParticleSpec second = scene.particles[0];  // a second fixed bedrock body
  second.uid = 3;
  second.position.y() += 10.0;
  scene.particles.push_back(second);
  const auto pairs = run::reducedPairs(scene);
  ASSERT_EQ(pairs.size(), 1u);  // rock/bedrock; rock/rock needs two rock blocks
  EXPECT_EQ(pairs[0], std::make_pair(0, 1));
  const setup::Setup reduced = run::reduceStrength(scene, 2.0);
  for (const auto& i : reduced.interactions) EXPECT_FALSE(i.a == 1 && i.b == 1);
}

// J-PLANAR-COHESION has joints "base" (friction 25 deg, 10 kPa) and "release" (0 deg) and the
// rock/rock pair (10 deg) for corners and edges.
TEST(StrengthReduction, ReducesOnlyTheNamedJoints) {
  const std::string file = std::string(POLYDEM_SCENES_DIR) + "/J-PLANAR-COHESION.toml";
  setup::Setup scene = scene::readScene(file);
  ASSERT_EQ(scene.joints.size(), 2u);
  // Naming nothing: every joint a free block touches and every usable pair.
  EXPECT_EQ(run::reducedJoints(scene), (std::vector<int>{0, 1}));
  EXPECT_EQ(run::reducedPairs(scene).size(), 1u);
  // Naming "base" only: the release joint and the pair keep their strength.
  scene.fos.joints = {0};
  scene.fos.joints_named = true;
  EXPECT_EQ(run::reducedJoints(scene), (std::vector<int>{0}));
  EXPECT_TRUE(run::reducedPairs(scene).empty());
  setup::Setup modified = scene;
  // So that a reduction of "release" would show.
  const auto phi = static_cast<std::size_t>(
      dynamics::parameterIndex(dynamics::jointLaw(modified.joints[1].law.law), "friction_angle"));
  modified.joints[1].law.values[phi] = 30.0;
  const setup::Setup reduced = run::reduceStrength(modified, 2.0);
  EXPECT_DOUBLE_EQ(std::tan(degToRad(reduced.joints[0].value("friction_angle"))),
                   std::tan(degToRad(25.0)) / 2.0);
  EXPECT_DOUBLE_EQ(reduced.joints[0].value("cohesion"), scene.joints[0].value("cohesion") / 2.0);
  EXPECT_DOUBLE_EQ(reduced.joints[1].value("friction_angle"), 30.0);
  EXPECT_EQ(reduced.interactions.size(), scene.interactions.size());
  // Naming a pair only: no joint is reduced.
  scene.fos.joints.clear();
  scene.fos.joints_named = false;
  scene.fos.interactions = {{0, 0}};
  EXPECT_TRUE(run::reducedJoints(scene).empty());
}

TEST(FosCriterion, DefaultsAndMissingMaxTime) {
  setup::Setup scene = scene::readScene(kExamples + "fos-incline.toml");
  scene.fos.settle_time.reset();
  const run::FosCriterion c = run::fosCriterion(scene);
  EXPECT_DOUBLE_EQ(c.window, 0.5);    // max_time / 4
  EXPECT_DOUBLE_EQ(c.time_cap, 8.0);  // 4 x max_time
  EXPECT_DOUBLE_EQ(c.local_damping, 0.8);
  EXPECT_FALSE(c.damping_from_scene);
  EXPECT_FALSE(c.displacement_limit);  // no length scale in the default criterion
  EXPECT_NE(c.describe().find("local damping 0.8"), std::string::npos) << c.describe();
  scene.fos.max_time.reset();
  try {
    run::fosCriterion(scene);
    FAIL() << "no error without max_time";
  } catch (const InputError& e) {
    EXPECT_GT(e.line(), 0);
    EXPECT_NE(std::string(e.what()).find("max_time"), std::string::npos);
  }
}

// The message of the InputError fosCriterion throws for `scene`, with its line.
std::string refusal(const setup::Setup& scene, int& line) {
  try {
    run::fosCriterion(scene);
  } catch (const InputError& e) {
    line = e.line();
    return e.what();
  }
  return "";
}

const std::string kInclineFos = R"(
[fos]
f_min = 0.5
f_max = 3
max_time = "2 s"
)";

// fos-incline.toml's text without its [fos] table, with `extra` appended.
setup::Setup inclineWith(const std::string& extra) {
  const std::string text = scene::readSceneText(kExamples + "fos-incline.toml");
  return scene::parseScene(text.substr(0, text.find("[fos]")) + extra, "incline.toml");
}

TEST(FosCriterion, RefusesAnInteractionNoContactUses) {
  // "clay" is a material no particle has: reducing it changes nothing, every trial is stable.
  setup::Setup scene = inclineWith(
      "[[material]]\nname = \"clay\"\ndensity = 2000\nkn = 1e9\nks = 5e8\n"
      "friction_angle = 20\n" +
      kInclineFos + "interactions = [[\"rock\", \"rock\"],\n  [\"clay\", \"rock\"]]\n");
  int line = 0;
  const std::string message = refusal(scene, line);
  EXPECT_NE(message.find("interactions[1]"), std::string::npos) << message;
  EXPECT_NE(message.find("no contact of the scene can use"), std::string::npos) << message;
  EXPECT_EQ(line, scene.fos.interaction_lines[1]);
  EXPECT_GT(line, scene.fos.line);
  // A pair of a material whose only particle is fixed, with itself: no contact either.
  setup::Setup fixed_only = inclineWith(kInclineFos + "interactions = [[\"rock\", \"rock\"]]\n");
  fixed_only.particles[1].fixed = true;
  EXPECT_NE(refusal(fixed_only, line).find("no contact"), std::string::npos);
}

TEST(FosCriterion, RefusesJointsThatNoFreeBlockTouchesOrAnEmptyChoice) {
  const std::string file = std::string(POLYDEM_SCENES_DIR) + "/J-PLANAR-COHESION.toml";
  const std::string text = [&] {
    std::ifstream in(file);
    return std::string(std::istreambuf_iterator<char>(in), {});
  }();
  const auto withFos = [&](const std::string& lines) {
    std::string t = text;
    t.replace(t.find("[fos]\n"), 6, "[fos]\n" + lines);
    return t;
  };
  // An unknown name: the reader refuses it with the file, the line and the known names.
  try {
    scene::parseScene(withFos("joints = [\"base\",\n  \"bsae\"]\n"), "planar.toml");
    ADD_FAILURE() << "an unknown joint was accepted";
  } catch (const InputError& e) {
    const std::string m = e.what();
    const int line =
        1 + static_cast<int>(std::count(
                text.begin(), text.begin() + static_cast<long>(text.find("[fos]")), '\n'));
    EXPECT_NE(m.find("planar.toml:" + std::to_string(line + 2)), std::string::npos) << m;
    EXPECT_NE(m.find("'bsae'"), std::string::npos) << m;
    EXPECT_NE(m.find("known: 'base', 'release'"), std::string::npos) << m;
  }
  // A joint only fixed rock has: the release plane's faces all belong to fixed blocks once no
  // free block is left.
  setup::Setup scene = scene::parseScene(withFos("joints = [\"release\"]\n"), "planar.toml");
  for (auto& p : scene.particles) p.fixed = true;
  int line = 0;
  EXPECT_NE(refusal(scene, line).find("no free block has a face"), std::string::npos);
  EXPECT_EQ(line, scene.fos.joint_lines[0]);
  // joints = [] with no interactions: nothing to reduce.
  setup::Setup empty = scene::parseScene(withFos("joints = []\n"), "planar.toml");
  EXPECT_NE(refusal(empty, line).find("nothing would be reduced"), std::string::npos);
}

TEST(FosCriterion, RefusesTrialsTooShortToJudge) {
  int line = 0;
  // 1e-3 s at dt = 1e-4 s: 10 steps.
  setup::Setup scene = inclineWith("[fos]\nf_min = 0.5\nf_max = 3\nmax_time = \"1e-3 s\"\n");
  std::string message = refusal(scene, line);
  EXPECT_NE(message.find("a trial needs at least 500 steps"), std::string::npos) << message;
  EXPECT_EQ(line, scene.fos.max_time_line);
  // check_every beyond the trial: the window would hold no evaluation.
  scene = inclineWith(kInclineFos + "check_every = 1e9\n");
  message = refusal(scene, line);
  EXPECT_NE(message.find("check_every = 1000000000"), std::string::npos) << message;
  EXPECT_NE(message.find("give check_every <= 1250"), std::string::npos) << message;
  EXPECT_EQ(line, scene.fos.check_every_line);
  scene = inclineWith(kInclineFos + "check_every = 1250\n");  // 4 evaluations a window
  EXPECT_EQ(refusal(scene, line), "");
}

// A search continued from trials already run: these decide every bound without a new trial.
run::FosResult continued(const std::vector<std::pair<double, std::string>>& trials) {
  log::setLevel(log::Level::kWarning);
  setup::Setup scene = scene::readScene(kExamples + "fos-incline.toml");
  run::FosResult prior;
  for (const auto& [f, outcome] : trials) {
    run::FosTrial t;
    t.factor = f;
    t.outcome = outcome;
    t.round = prior.rounds_complete++;
    prior.trials.push_back(t);
  }
  return run::findFactorOfSafety(scene, run::fosCriterion(scene), 1, MPI_COMM_WORLD, &prior);
}

TEST(FosBracket, ReportsOnlyBoundsOfDecidedTrials) {
  // Undecided at f_min: nothing is bracketed, and nothing is claimed below f_min.
  run::FosResult r = continued({{0.5, "undecided"}});
  EXPECT_FALSE(r.failed);
  EXPECT_FALSE(r.factor());
  EXPECT_NE(r.note.find("undecided"), std::string::npos) << r.note;
  // Failed at f_min, a decided trial: below the range, and said so.
  r = continued({{0.5, "failed"}});
  EXPECT_EQ(r.failed, 0.5);
  EXPECT_FALSE(r.factor());
  EXPECT_NE(r.note.find("failed (a decided trial)"), std::string::npos) << r.note;
  // Stable at f_min, undecided at f_max: not "above f_max".
  r = continued({{0.5, "stable"}, {3.0, "undecided"}});
  EXPECT_EQ(r.stable, 0.5);
  EXPECT_FALSE(r.failed);
  EXPECT_EQ(r.note.find("above f_max"), std::string::npos) << r.note;
  EXPECT_NE(r.note.find("not bracketed"), std::string::npos) << r.note;
  // An undecided trial inside the bracket stops the search: the bracket of the decided trials,
  // and no factor of safety claimed to the resolution.
  r = continued({{0.5, "stable"}, {3.0, "failed"}, {1.75, "undecided"}});
  EXPECT_EQ(r.stable, 0.5);
  EXPECT_EQ(r.failed, 3.0);
  EXPECT_FALSE(r.resolved);
  EXPECT_FALSE(r.factor());
  EXPECT_NE(r.note.find("1.75 is undecided"), std::string::npos) << r.note;
  EXPECT_EQ(r.trials.size(), 3u);  // no trial was run
}

}  // namespace
}  // namespace polydem::sim
