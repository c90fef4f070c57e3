// Shortened runs of the validation scenes of benchmark_scenes/, asserting their analytical
// answers (BENCHMARKS.md sections S and D) for the kernels that must get them right. The full
// runs, for every kernel, are in the README's results table (scripts/validation-table).
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "core/logging.h"
#include "core/strings.h"
#include "io/scene_reader.h"
#include "sim/run.h"

namespace polydem::sim {
namespace {

struct Case {
  const char* scene;
  const char* kernel;
  double end_time;  // shortened; 0 = the scene's own
  // Checks known to fail, by a part of their name, with the reason (the README's table says the
  // same). They are asserted to fail, so that a fix shows up here and the table gets updated.
  std::vector<std::string> known_failures = {};
  const char* reason = nullptr;
};

std::ostream& operator<<(std::ostream& out, const Case& c) {
  return out << c.scene << " with " << c.kernel;
}

// Why the stopped block of mu = 0.6 creeps (measured, docs/dynamics.md): with one contact point
// and undamped springs, the shear spring overshoots to twice m g sin(theta) when the block stops,
// the block rocks on its base and hops, and slides down in steps although tan 30 deg < 0.6. The
// same rocking after the turn lowers the mean friction of the mu = 0.4 blocks of the softest and
// stiffest kn by 1-2 %.
constexpr const char* kRocking =
    "undamped single-point contact: the stopped block rocks and creeps down the slope";

// D-PILLAR (Zhao section 5.4): a stack of 6 rigid blocks on springs disperses the compression
// wave, so the front block leaves at 2.39e-3 s, as a chain of 6 masses does
// (benchmark_scenes/tools/pillar_chain.py), not at the continuum's 6 L / V = 1.64e-3 s.
constexpr const char* kDispersion =
    "the wave front disperses over a stack of 6 blocks: the front block leaves later than 6 L / V";

bool isKnownFailure(const Case& c, const std::string& check_name) {
  return std::any_of(
      c.known_failures.begin(), c.known_failures.end(),
      [&](const std::string& part) { return check_name.find(part) != std::string::npos; });
}

class ValidationScene : public ::testing::TestWithParam<Case> {};

TEST_P(ValidationScene, ChecksPass) {
  const Case& c = GetParam();
  log::setLevel(log::Level::kWarning);
  const io::Scene scene = io::readScene(std::string(POLYDEM_SCENES_DIR) + "/" + c.scene + ".toml");
  RunOptions options;
  options.kernel = c.kernel;
  if (c.end_time > 0) options.end_time = c.end_time;
  const RunResult result = runScene(scene, options, MPI_COMM_WORLD);
  ASSERT_FALSE(result.checks.empty());
  for (const auto& check : result.checks) {
    const bool known = isKnownFailure(c, check.name);
    EXPECT_EQ(check.pass, !known) << c << ": " << check.name << " = " << check.value << " ("
                                  << check.compare << " " << check.expected << ") " << check.note
                                  << (known ? cat(" [listed as a known failure: ", c.reason, "]")
                                            : std::string());
  }
  EXPECT_EQ(result.hash.history_conflicts, 0);
}

INSTANTIATE_TEST_SUITE_P(
    Scenes, ValidationScene,
    ::testing::Values(
        // Zhao eqs. 41-42, within 1 %: mu = 0.2 and 0.4 slide back, mu = 0.6 stops (t1 < 0.72 s).
        // fcp takes its point from the deepest features, so a tilt moves it at once (a restoring
        // moment): it rocks less and stays within 1 %.
        Case{"D-SLIDING-BLOCK", "fcp", 1.2},
        Case{"D-SLIDING-BLOCK", "fcp-ipm", 1.2, {"mu 0.6"}, kRocking},
        Case{"D-SLIDING-BLOCK", "gjk-epa-ipm", 1.2, {"mu 0.6"}, kRocking},
        Case{"D-SLIDING-BLOCK-KN", "fcp-ipm", 1.2, {"kn 1.5e+07", "kn 1.5e+09"}, kRocking},
        // Zhao eq. 45, within 1 %.
        Case{"D-WEDGE-SLIDE", "fcp-ipm", 0.6}, Case{"D-WEDGE-SLIDE", "gjk-epa-ipm", 0.6},
        // Keissar figs. 2.9-2.10: no drift, no rotation with IPM / FCP.
        Case{"S-BLOCK-ON-PLANE", "gjk-epa-ipm", 1.0}, Case{"S-BLOCK-ON-PLANE", "fcp-ipm", 1.0},
        Case{"D-BOUNCING-CUBES", "gjk-epa-ipm", 1.5}, Case{"D-BOUNCING-CUBES", "fcp-ipm", 1.5},
        // Zhao section 5.1: rebound without drift and energy loss.
        Case{"D-TETRA-IMPACT", "distance-potential", 0.0},
        // Zhao section 5.4, at full length (4 ms).
        Case{"D-PILLAR", "gjk-epa-ipm", 0.0, {"vs wave speed"}, kDispersion}),
    [](const ::testing::TestParamInfo<Case>& param_info) {
      std::string name = std::string(param_info.param.scene) + "_" + param_info.param.kernel;
      for (char& ch : name) ch = std::isalnum(static_cast<unsigned char>(ch)) ? ch : '_';
      return name;
    });

}  // namespace
}  // namespace polydem::sim
