// Every [[check]] kind declared under scene/check_kinds/ is one run/checks/ computes (the
// registry of run/check_registry.h has it), and the simulation
// reads only the parameters the kind declares: a scene with each kind, all its
// parameters given, builds its checks.
#include <gtest/gtest.h>

#include "polydem/core/error.h"
#include "polydem/core/strings.h"
#include "polydem/run/check_registry.h"
#include "polydem/run/checks.h"
#include "polydem/scene/check_kinds.h"
#include "polydem/scene/scene_reader.h"

namespace polydem::sim {
namespace {

const char* const kScene = R"([scene]
id = "T-CHECK-KINDS"
[simulation]
dt = 1e-4
steps = 10
[[material]]
name = "rock"
density = 2500
kn = 1e9
[[shape]]
name = "cube"
type = "cube"
edge = 1
[[driver]]
name = "tilt"
angular_velocity = [0, 0.03, 0]
[[particle]]
label = "a"
shape = "cube"
material = "rock"
[[particle]]
label = "b"
shape = "cube"
material = "rock"
position = [2, 0, 0]
[[particle]]
label = "p"
shape = "cube"
material = "rock"
position = [0, 0, -2]
driver = "tilt"
)";

/// A valid TOML value for a declared parameter.
std::string valueOf(const scene::CheckParam& p) {
  switch (p.type) {
    case scene::CheckParamType::kNumber:
      return std::isfinite(p.hi) ? cat(0.5 * (p.lo + p.hi)) : cat(p.lo + 1.0);
    case scene::CheckParamType::kDirection:
      return "[1, 0, 1]";
    case scene::CheckParamType::kParticles:
      return "\"a, b\"";  // pair_separation takes two
    case scene::CheckParamType::kParticle:
      return p.name == "platform" ? "\"p\"" : "\"a\"";  // tilt_failure's is driven
    case scene::CheckParamType::kText:
      return "\"a\"";  // a label prefix
    case scene::CheckParamType::kWord:
      return cat("\"", p.words.back(), "\"");
  }
  return "";
}

TEST(CheckKinds, EveryDeclaredKindIsComputedFromItsDeclaredParameters) {
  for (const auto& kind : scene::checkKinds()) {
    std::string text =
        cat(kScene, "[[check]]\nname = \"c\"\nkind = \"", kind.name, "\"\ncompare = \"report\"\n");
    for (const auto& p : kind.params) text += cat(p.name, " = ", valueOf(p), "\n");
    const setup::Setup scene = scene::parseScene(text, "kinds.toml");
    run::Tracker tracker;
    std::vector<std::unique_ptr<run::Check>> checks;
    EXPECT_NO_THROW(checks = run::makeChecks(scene, tracker)) << kind.name;
    ASSERT_EQ(checks.size(), 1u) << kind.name;
    EXPECT_EQ(checks[0]->spec().kind, kind.name);
  }
}

TEST(CheckKinds, TheRegistryHoldsExactlyTheDeclaredKindsInOrder) {
  std::vector<std::string> declared;
  for (const auto& kind : scene::checkKinds()) declared.emplace_back(kind.name);
  const auto registered = run::registeredCheckKinds();
  ASSERT_GE(registered.size(), declared.size());
  EXPECT_EQ(std::vector<std::string>(registered.begin(), registered.begin() + declared.size()),
            declared);
}

// A program's own kind: registered once, built by makeChecks from a setup made in C++.
class ConstantCheck : public run::Check {
 public:
  explicit ConstantCheck(const setup::CheckSpec& spec) : run::Check(spec) {}
  void observe(const Simulation&, const run::Tracker&) override {}
  double value(Simulation&) override { return 42.0; }
};

TEST(CheckKinds, AProgramRegistersAKindOfItsOwn) {
  run::registerCheckKind("test_constant",
                         [](const setup::Setup&, const setup::CheckSpec& spec, run::Tracker&) {
                           return std::make_unique<ConstantCheck>(spec);
                         });
  EXPECT_THROW(
      run::registerCheckKind("test_constant",
                             [](const setup::Setup&, const setup::CheckSpec& spec, run::Tracker&) {
                               return std::make_unique<ConstantCheck>(spec);
                             }),
      Error);
  EXPECT_THROW(
      run::registerCheckKind("displacement",
                             [](const setup::Setup&, const setup::CheckSpec& spec, run::Tracker&) {
                               return std::make_unique<ConstantCheck>(spec);
                             }),
      Error);
  setup::Setup scene = scene::parseScene(kScene, "kinds.toml");
  setup::CheckSpec spec;
  spec.name = "mine";
  spec.kind = "test_constant";
  scene.checks.push_back(spec);
  run::Tracker tracker;
  const auto checks = run::makeChecks(scene, tracker);
  ASSERT_EQ(checks.size(), 1u);
  EXPECT_EQ(checks[0]->spec().kind, "test_constant");
  spec.kind = "no_such_kind";
  scene.checks = {spec};
  EXPECT_THROW(run::makeChecks(scene, tracker), InputError);
}

}  // namespace
}  // namespace polydem::sim
