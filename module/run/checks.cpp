// Building and evaluating a scene's checks; the kinds are in checks/, one file each, registered
// in checks/check_table.cpp.
#include "polydem/run/checks.h"

#include "polydem/core/error.h"
#include "polydem/core/strings.h"
#include "polydem/run/check_registry.h"
#include "polydem/run/checks/params.h"
#include "polydem/scene/check_kinds.h"

namespace polydem::run {

Uid uidOfLabel(const setup::Setup& scene, const std::string& label) {
  for (const auto& p : scene.particles) {
    if (p.label == label) return p.uid;
  }
  return 0;
}

std::vector<std::unique_ptr<Check>> makeChecks(const setup::Setup& scene, Tracker& tracker) {
  std::vector<std::unique_ptr<Check>> checks;
  for (const auto& spec : scene.checks) {
    const CheckFactory* make = findCheckFactory(spec.kind);
    if (!make) Params(scene, spec).fail("unknown kind; known kinds: " + scene::checkKindNames());
    auto check = (*make)(scene, spec, tracker);
    if (!check) {
      throw Error(cat("check kind '", spec.kind, "' built no check for '", spec.name, "'"));
    }
    checks.push_back(std::move(check));
  }
  return checks;
}

std::vector<output::CheckResult> evaluateChecks(std::vector<std::unique_ptr<Check>>& checks,
                                                sim::Simulation& sim) {
  std::vector<output::CheckResult> results;
  for (auto& c : checks) {
    const auto& s = c->spec();
    output::CheckResult r;
    r.name = s.name;
    r.kind = s.kind;
    r.value = c->value(sim);
    if (const scene::CheckKind* kind = scene::findCheckKind(s.kind)) {
      r.unit = scene::storedUnit(scene::valueQuantity(*kind, s));
    }
    r.expected = s.expected;
    r.tolerance = s.tolerance;
    r.compare = s.compare;
    r.reference = s.reference;
    r.note = c->note;
    r.pass = output::checkPasses(s.compare, r.value, s.expected, s.tolerance);
    results.push_back(r);
  }
  return results;
}

}  // namespace polydem::run
