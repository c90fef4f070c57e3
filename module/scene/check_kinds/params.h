// Builders of the parameter declarations the check kinds share (CheckParam, check_kinds.h).
#pragma once

#include <limits>
#include <string_view>
#include <utility>
#include <vector>

#include "polydem/scene/check_kinds.h"

namespace polydem::scene::kinds {

inline constexpr double kInf = std::numeric_limits<double>::infinity();

inline CheckParam particles(std::string_view help = "labels of the particles, comma-separated") {
  return {"particle", CheckParamType::kParticles, true, {}, -kInf, kInf, false, false, {}, help};
}
inline CheckParam particle() {
  return {"particle", CheckParamType::kParticle, true, {}, -kInf, kInf, false, false, {},
          "its label"};
}
inline CheckParam direction(std::string_view name, bool required, std::string_view help) {
  return {name, CheckParamType::kDirection, required, {}, -kInf, kInf, false, false, {}, help};
}
inline CheckParam number(std::string_view name, bool required, Quantity q, double lo, double hi,
                         bool lo_open, bool hi_open, std::string_view help) {
  return {name, CheckParamType::kNumber, required, q, lo, hi, lo_open, hi_open, {}, help};
}
inline CheckParam word(std::string_view name, std::vector<std::string_view> words,
                       std::string_view help, bool required = false) {
  return {name,  CheckParamType::kWord, required, {}, -kInf, kInf, false,
          false, std::move(words),      help};
}
inline CheckParam labelPrefix(bool required) {
  return {"label_prefix",
          CheckParamType::kText,
          required,
          {},
          -kInf,
          kInf,
          false,
          false,
          {},
          "the blocks' label prefix (prefix_0, prefix_1, ...; default: every free block)"};
}
/// A number in the unit of what the check measures (CheckParam::measured).
inline CheckParam measuredNumber(std::string_view name, std::string_view help) {
  CheckParam p = number(name, false, Quantity::kDimensionless, 0.0, kInf, false, false, help);
  p.measured = true;
  return p;
}

// The incline and the gravity of the analytical curves (Zhao eqs. 41-42 and 45).
inline CheckParam theta(bool zero_allowed) {
  return number("theta", true, Quantity::kAngle, 0.0, 90.0, !zero_allowed, false,
                "inclination of the plane (of the intersection line for a wedge), degrees");
}
inline CheckParam gravity() {
  return number("g", false, Quantity::kAcceleration, 0.0, kInf, true, false,
                "gravity of the analytical curve (default: |[simulation] gravity|)");
}

}  // namespace polydem::scene::kinds
