#include "polydem/dynamics/joint_law.h"

#include <cmath>

#include "polydem/core/error.h"
#include "polydem/core/strings.h"
#include "polydem/dynamics/joint_laws.h"

namespace polydem::dynamics {

namespace {

template <typename Law>
constexpr JointLawInfo info(JointLaw id) {
  static_assert(Law::kHistoryColumns.size() <= particles::kMaxLawHistory,
                "a law keeps at most kMaxLawHistory history values per sub-contact");
  return {Law::kName,           id,
          Law::kDescription,    Law::kParameters,
          Law::kHistoryColumns, Law::kReducesMobilizedStrength};
}

const std::vector<JointLawInfo>& registry() {
  static const std::vector<JointLawInfo> laws{
#define POLYDEM_JOINT_LAW(id, type) info<type>(JointLaw::id),
#include "polydem/dynamics/joint_law_list.inc"
#undef POLYDEM_JOINT_LAW
  };
  return laws;
}

template <typename Law>
void lawCoefficients(std::span<const double> values, LawCoefficients& k) {
  Law::coefficients(values, k);
}

}  // namespace

std::span<const JointLawInfo> jointLaws() {
  return registry();
}

const JointLawInfo* findJointLaw(std::string_view name) {
  for (const auto& law : registry()) {
    if (name == law.name) return &law;
  }
  return nullptr;
}

const JointLawInfo& jointLaw(JointLaw id) {
  return registry()[static_cast<std::size_t>(id)];
}

int parameterIndex(const JointLawInfo& info, std::string_view name) {
  for (std::size_t i = 0; i < info.parameters.size(); ++i) {
    if (name == info.parameters[i].name) return static_cast<int>(i);
  }
  return -1;
}

JointParameters reduceJointStrength(const JointParameters& joint, double factor) {
  if (!(factor > 0.0) || !std::isfinite(factor)) {
    throw Error(cat("strength reduction: the factor must be > 0, got ", factor));
  }
  const JointLawInfo& law = jointLaw(joint.law);
  JointParameters out = joint;
  for (std::size_t i = 0; i < law.parameters.size() && i < out.values.size(); ++i) {
    double& v = out.values[i];
    switch (law.parameters[i].reduction) {
      case Reduction::kNone:
        break;
      case Reduction::kTangent:
        v = radToDeg(std::atan(std::tan(degToRad(v)) / factor));
        break;
      case Reduction::kDivide:
        v /= factor;
        break;
    }
  }
  if (law.reduces_mobilized_strength) out.strength_divisor *= factor;
  return out;
}

LawCoefficients jointCoefficients(const JointParameters& joint, const LawCoefficients& pair,
                                  std::optional<double> friction_angle_deg) {
  const JointLawInfo& law = jointLaw(joint.law);
  if (joint.values.size() != law.parameters.size()) {
    throw Error(cat("joint law ", law.name, ": ", joint.values.size(), " parameters, expected ",
                    law.parameters.size()));
  }
  const std::vector<double>& values = joint.values;
  for (std::size_t i = 0; i < values.size(); ++i) {
    const LawParameter& p = law.parameters[i];
    const double v = values[i];
    const bool above = p.min_inclusive ? v >= p.min : v > p.min;
    const bool below = p.max_inclusive ? v <= p.max : v < p.max;
    if (!(above && below)) {
      throw Error(cat("joint law ", law.name, ": ", p.name, " = ", v, " is outside ",
                      p.min_inclusive ? "[" : "(", p.min, ", ", p.max,
                      p.max_inclusive ? "]" : ")"));
    }
  }
  if (!(joint.strength_divisor > 0.0)) {
    throw Error(cat("joint law ", law.name, ": strength divisor ", joint.strength_divisor));
  }
  LawCoefficients k = pair;
  k.law = joint.law;
  k.strength_divisor = joint.strength_divisor;
  switch (joint.law) {
#define POLYDEM_JOINT_LAW(id, type)   \
  case JointLaw::id:                  \
    lawCoefficients<type>(values, k); \
    break;
#include "polydem/dynamics/joint_law_list.inc"
#undef POLYDEM_JOINT_LAW
  }
  // The initial-equilibrium stage (Keissar section 3.3): every joint holds by Coulomb friction at
  // the stage's angle with its own stiffness, cohesion and tensile strength; no law keeps history
  // in it (nothing breaks, nothing is mobilized while the blocks settle).
  if (friction_angle_deg) {
    const double phi = *friction_angle_deg;
    if (!(phi >= 0.0 && phi < 90.0)) {
      throw Error(cat("joint law: friction angle ", phi, " deg is outside [0, 90)"));
    }
    k.law = JointLaw::kCoulomb;
    k.tan_friction = std::tan(degToRad(phi));
    k.strength_divisor = 1.0;
  }
  return k;
}

}  // namespace polydem::dynamics
