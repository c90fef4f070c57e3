// The joint law `coulomb` (3DEC's Coulomb slip): tau_max = c + sigma tan(phi), the normal spring
// may pull down to -tensile_strength. Material pairs without a joint take this law too, with their
// cohesion as a force per pair (dynamics/sub_contact_law.h gives the sub-contact equations).
//
// Hooks of a law, called by the sub-contact loop (sub_contact_law.cpp) for each sub-contact of a
// pair on the joint; `h` is the sub-contact's history values (kHistoryColumns of them):
//   Pair prepare(k, area)                      per pair and step: what depends on the area
//   inherit(old_keys, old, fc, h)              history of a sub-contact that appears in the pair
//   effectiveGap(gap, h), openGap(h, g0), tension(h, t0)
//                                              the gap the springs see, the gap at which the
//                                              sub-contact opens and its tensile force (per pair:
//                                              g0, t0 as for Coulomb)
//   cap(pair, k, f_elastic, w, cohesion, gap, slide, h)
//                                              the shear cap (N); slide = |v_t| dt this step
//   slipped(pair, k, gap, slide, h)            the shear exceeded the cap this step
//   keepOpen(had_history, h)                   whether an opened sub-contact keeps its history
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <span>

#include "polydem/contact/face/face_contact.h"
#include "polydem/dynamics/joint_law.h"
#include "polydem/particles/contact_history.h"

namespace polydem::dynamics {

struct CoulombLaw {
  static constexpr const char* kName = "coulomb";
  static constexpr const char* kDescription =
      "Coulomb slip: tau = c + sigma tan(phi), tension up to tensile_strength";
  static constexpr std::array<LawParameter, 5> kParameters{{
      {"jkn", ParameterUnit::kJointStiffness, 0.0, 1e300, false, true, true, 0.0, nullptr,
       Reduction::kNone, "normal stiffness per area"},
      {"jks", ParameterUnit::kJointStiffness, 0.0, 1e300, false, true, true, 0.0, nullptr,
       Reduction::kNone, "shear stiffness per area"},
      {"friction_angle", ParameterUnit::kAngle, 0.0, 90.0, true, false, true, 0.0, nullptr,
       Reduction::kTangent, "friction angle phi"},
      {"cohesion", ParameterUnit::kPressure, 0.0, 1e300, true, true, false, 0.0, nullptr,
       Reduction::kDivide, "cohesion c"},
      {"tensile_strength", ParameterUnit::kPressure, 0.0, 1e300, true, true, false, 0.0, nullptr,
       Reduction::kDivide, "tensile strength sigma_t"},
  }};
  static constexpr std::array<const char*, 0> kHistoryColumns{};
  static constexpr bool kReducesMobilizedStrength = false;

  /// p in the order of kParameters.
  static void coefficients(std::span<const double> p, LawCoefficients& k) {
    k.jkn = p[0];
    k.jks = p[1];
    k.tan_friction = std::tan(degToRad(p[2]));
    k.cohesion = 0.0;
    k.cohesion_stress = p[3];
    k.tensile_strength = p[4];
  }

  struct Pair {};
  static Pair prepare(const LawCoefficients&, double) { return {}; }
  static void inherit(std::span<const particles::SubFeature>,
                      std::span<const particles::SubHistory>, const contact::FaceContact&,
                      double*) {}
  static double effectiveGap(double gap, const double*) { return gap; }
  static double openGap(const double*, double open_gap) { return open_gap; }
  static double tension(const double*, double tension) { return tension; }
  // In tension (f_elastic < 0) friction lowers the cap, never below 0.
  static double cap(const Pair&, const LawCoefficients& k, double f_elastic, double w,
                    double cohesion, double, double, double*) {
    return std::max(f_elastic * k.tan_friction + w * cohesion, 0.0);
  }
  static void slipped(const Pair&, const LawCoefficients&, double, double, double*) {}
  static bool keepOpen(bool, double*) { return false; }
};

}  // namespace polydem::dynamics
