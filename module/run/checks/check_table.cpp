// The registry of check kinds: kind name -> the factory that builds its Check. The built-in kinds
// are the table below, one file each in this folder; their parameters are declared in the file of
// the same name under module/scene/check_kinds/ (ctest run_check_kinds asserts both lists agree).
// Programs add their own with registerCheckKind().
#include <string>
#include <vector>

#include "polydem/core/error.h"
#include "polydem/core/strings.h"
#include "polydem/run/check_registry.h"
#include "polydem/run/checks/kinds.h"

namespace polydem::run {

namespace {

struct KindEntry {
  std::string kind;
  CheckFactory make;
};

// The built-in kinds, in the order of docs/scene-format.md; then those registered by programs.
std::vector<KindEntry>& registry() {
  static std::vector<KindEntry> table = {
      {"displacement", kinds::displacement},
      {"rotation", kinds::rotation},
      {"lateral_drift", kinds::lateralDrift},
      {"sliding_block", kinds::slidingBlock},
      {"wedge_slide", kinds::wedgeSlide},
      {"kinetic_energy_ratio", kinds::kineticEnergyRatio},
      {"separation_time", kinds::separationTime},
      {"equilibrium_steps", kinds::equilibriumSteps},
      {"mean_speed", kinds::meanSpeed},
      {"max_speed", kinds::maxSpeed},
      {"contact_count", kinds::contactCount},
      {"max_contact_force", kinds::maxContactForce},
      {"free_motion", kinds::freeMotion},
      {"tilt_failure", kinds::tiltFailure},
      {"pair_separation", kinds::pairSeparation},
  };
  return table;
}

}  // namespace

void registerCheckKind(std::string kind, CheckFactory factory) {
  if (kind.empty()) throw Error("registerCheckKind: a check kind needs a name");
  if (!factory) throw Error(cat("registerCheckKind: check kind '", kind, "' has no factory"));
  if (findCheckFactory(kind)) {
    throw Error(cat("registerCheckKind: check kind '", kind, "' is already registered"));
  }
  registry().push_back({std::move(kind), std::move(factory)});
}

const CheckFactory* findCheckFactory(std::string_view kind) {
  for (const auto& k : registry()) {
    if (k.kind == kind) return &k.make;
  }
  return nullptr;
}

std::vector<std::string> registeredCheckKinds() {
  std::vector<std::string> names;
  for (const auto& k : registry()) names.push_back(k.kind);
  return names;
}

}  // namespace polydem::run
