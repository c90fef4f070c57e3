// The joint-law interface: every law a [[joint]] may name, what it declares, and the per-pair
// coefficients the hot loop reads (dynamics/sub_contact_law.h).
//
// A law is one header (joint_law_<name>.h) and one line in joint_law_list.inc. Its header
// declares a struct with
//   - kName, kDescription;
//   - kParameters: name, unit kind, range, default, and how strength reduction by a factor F
//     scales it (LawParameter below); the scene reader, Python and polydem fos read them from here;
//   - kHistoryColumns: the names of its per-sub-contact history values (their number is the size
//     of its history; at most kMaxLawHistory), the checkpoint's /subcontacts/law_state columns;
//   - coefficients(): its parameters into the LawCoefficients of one joint;
//   - the hooks the sub-contact loop calls for each sub-contact (see joint_law_coulomb.h, the
//     simplest, for the list). The loop is a template instantiated once per law and chosen by a
//     switch per pair: no virtual call and no allocation per sub-contact.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "polydem/dynamics/contact_law.h"

namespace polydem::dynamics {

/// The unit kind of a law parameter, as the scene reader checks it.
enum class ParameterUnit : std::uint8_t {
  kJointStiffness,  // Pa/m
  kPressure,        // Pa
  kAngle,           // degrees
  kLength,          // m
  kDimensionless,   // a plain number
  kFlag,            // true/false, stored 1/0
};

/// How `polydem fos` reduces a parameter by the factor F.
enum class Reduction : std::uint8_t {
  kNone,     // unchanged (stiffness, lengths, roughness)
  kTangent,  // an angle phi becomes atan(tan(phi) / F)
  kDivide,   // a strength x becomes x / F
};

/// One parameter of a law, in SI units (angles in degrees).
struct LawParameter {
  const char* name;
  ParameterUnit unit;
  double min, max;  // the allowed range
  bool min_inclusive, max_inclusive;
  bool required;             // no default: the scene must give it
  double fallback;           // the default, when not required and `default_from` is null
  const char* default_from;  // the default is this other parameter's value (or null)
  Reduction reduction;
  const char* description;
};

/// Everything the reader, Python, fos and the checkpoint need of a law.
struct JointLawInfo {
  const char* name;
  JointLaw id;
  const char* description;
  std::span<const LawParameter> parameters;
  std::span<const char* const> history_columns;
  /// Strength reduction divides the law's mobilized shear strength itself (its strength is not a
  /// parameter that F can scale, Barton-Bandis): polydem fos multiplies the joint's
  /// strength_divisor by F.
  bool reduces_mobilized_strength;
};

/// Every law, in the order of joint_law_list.inc.
std::span<const JointLawInfo> jointLaws();
/// The law named `name`, or null.
const JointLawInfo* findJointLaw(std::string_view name);
/// The law of id `id`.
const JointLawInfo& jointLaw(JointLaw id);
/// Index of parameter `name` in info.parameters, or -1.
int parameterIndex(const JointLawInfo& info, std::string_view name);

/// A joint's law and its parameter values (in the order of its law's kParameters, SI units).
struct JointParameters {
  JointLaw law = JointLaw::kCoulomb;
  std::vector<double> values;
  double strength_divisor = 1.0;  // > 1 under strength reduction of laws that need it
};

/// The joint's parameters reduced by the factor F (docs/scene-format.md, "Strength reduction"):
/// each parameter by its Reduction, and strength_divisor * F for laws whose mobilized strength is
/// reduced as a whole. Throws polydem::Error for F <= 0 or not finite.
JointParameters reduceJointStrength(const JointParameters& joint, double factor);

/// Coefficients of a face contact on a joint: the joint's law and parameters; kn, ks (not used by
/// a face contact with jkn, jks > 0), penalty and damping are the material pair's `pair`, so the
/// joint changes what a rock engineer gives for it and nothing numerical.
/// `friction_angle_deg`, when given (the initial-equilibrium stage), makes the joint Coulomb at
/// that angle with its own stiffness, cohesion and tensile strength. Throws polydem::Error for
/// values outside their law's ranges.
LawCoefficients jointCoefficients(const JointParameters& joint, const LawCoefficients& pair,
                                  std::optional<double> friction_angle_deg = std::nullopt);

}  // namespace polydem::dynamics
