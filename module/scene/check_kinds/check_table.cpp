// The table of check-kind declarations (one file per kind in this folder) and its look-ups.
#include "polydem/scene/check_kinds.h"

#include <string>

#include "polydem/scene/check_kinds/kinds.h"
#include "polydem/setup/setup.h"

namespace polydem::scene {

namespace {

// The built-in kinds, in the order of docs/scene-format.md.
std::vector<CheckKind> makeKinds() {
  return {kinds::displacement(),   kinds::rotation(),         kinds::lateralDrift(),
          kinds::slidingBlock(),   kinds::wedgeSlide(),       kinds::kineticEnergyRatio(),
          kinds::separationTime(), kinds::equilibriumSteps(), kinds::meanSpeed(),
          kinds::maxSpeed(),       kinds::contactCount(),     kinds::maxContactForce(),
          kinds::freeMotion(),     kinds::tiltFailure(),      kinds::pairSeparation()};
}

}  // namespace

const std::vector<CheckKind>& checkKinds() {
  static const std::vector<CheckKind> kinds = makeKinds();
  return kinds;
}

const CheckKind* findCheckKind(std::string_view name) {
  for (const auto& k : checkKinds()) {
    if (k.name == name) return &k;
  }
  return nullptr;
}

const CheckParam* findCheckParam(const CheckKind& kind, std::string_view name) {
  for (const auto& p : kind.params) {
    if (p.name == name) return &p;
  }
  return nullptr;
}

Quantity measuredQuantity(const CheckKind& kind, const setup::CheckSpec& spec) {
  if (kind.name != "free_motion") return kind.value;
  const auto it = spec.strings.find("quantity");
  const std::string q = it == spec.strings.end() ? std::string() : it->second;
  if (q == "mean_speed" || q == "max_speed") return Quantity::kVelocity;
  if (q == "max_angular_speed") return Quantity::kAngularVelocity;
  return Quantity::kLength;  // displacements and the front's advance
}

Quantity valueQuantity(const CheckKind& kind, const setup::CheckSpec& spec) {
  const auto at = spec.strings.find("at");
  if (kind.name == "free_motion" && at != spec.strings.end() && at->second == "first_below") {
    return Quantity::kTime;
  }
  return measuredQuantity(kind, spec);
}

std::string checkKindNames() {
  std::string out;
  for (const auto& k : checkKinds()) out += (out.empty() ? "" : ", ") + std::string(k.name);
  return out;
}

}  // namespace polydem::scene
