// The joint law `barton-bandis`: the shear strength of a rough rock joint from its roughness
// (JRC), wall strength (JCS) and residual friction angle phi_r under the normal stress sigma
// (Barton 1973; Barton & Choubey 1977), with Bandis' scale correction to the field length (Barton
// & Bandis 1982) and the strength mobilized along the shear displacement (Barton 1982):
//
//   JRC_n = JRC_0 (L_n / L_0)^(-0.02 JRC_0),   JCS_n = JCS_0 (L_n / L_0)^(-0.03 JRC_0),
//   i(sigma) = JRC_n log10(JCS_n / sigma)  (0 when sigma >= JCS_n),
//   delta_p = (L_n / 500) (JRC_n / L_n)^0.33      (lengths in m),
//   tau = sigma tan(min(phi_r + m(delta / delta_p) i(sigma), 70 deg)),  0 for sigma <= 0,
//
// m = JRC_mob / JRC_n the table of kMobilization (linear between its points, 0 beyond the last;
// its first point is -phi_r / i, so that the mobilized angle is 0 at delta = 0, or 0 when i = 0).
// L_n is field_length, or sqrt(A) of the face contact at that step when field_length is 0.
// sigma = jkn g per sub-contact (g its gap plus its dilation opening); no cohesion, no tension.
//
// History, two values per sub-contact: `shear_displacement` delta, the sum over steps of
// |v_t| dt, and `dilation_opening`, with dilation = true the sum while slipping of
// tan(d_mob) |v_t| dt, d_mob = 0.5 max(m, 0) i (Barton & Choubey 1977), which adds to the
// sub-contact's gap: dilation starts at 0.3 delta_p, where the mobilized angle reaches phi_r. A
// sub-contact that appears in a pair takes the mean of the pair's sub-contacts of the last step (a
// corner that appears in a sheared joint has been sheared as far as its neighbours).
#pragma once

#include <cmath>

#include "polydem/dynamics/joint_law_coulomb.h"

namespace polydem::dynamics {

/// The scale-corrected roughness and wall strength and the peak displacement of a joint of
/// length L_n (Barton & Bandis 1982).
struct BartonBandisScale {
  double jrc = 0.0;      // JRC_n
  double jcs = 0.0;      // JCS_n, Pa
  double delta_p = 0.0;  // m
};

inline BartonBandisScale bartonBandisScale(double jrc0, double jcs0, double lab_length,
                                           double field_length) {
  const double ratio = field_length / lab_length;
  BartonBandisScale s;
  s.jrc = jrc0 * std::pow(ratio, -0.02 * jrc0);
  s.jcs = jcs0 * std::pow(ratio, -0.03 * jrc0);
  s.delta_p = field_length / 500.0 * std::pow(s.jrc / field_length, 0.33);
  return s;
}

/// The roughness angle i(sigma) in degrees: JRC_n log10(JCS_n / sigma), 0 for sigma >= JCS_n or
/// sigma <= 0.
inline double bartonBandisRoughness(const BartonBandisScale& s, double sigma) {
  return sigma > 0.0 && sigma < s.jcs ? s.jrc * std::log10(s.jcs / sigma) : 0.0;
}

/// Barton's (1982) table of the mobilized roughness JRC_mob / JRC_n against delta / delta_p.
inline constexpr std::array<double, 8> kMobilizationDisplacement{0.0, 0.3, 0.6,  1.0,
                                                                 2.0, 4.0, 10.0, 100.0};
inline constexpr std::array<double, 8> kMobilizationRoughness{0.0,  0.0,  0.75, 1.0,
                                                              0.85, 0.70, 0.50, 0.0};

/// JRC_mob / JRC_n at delta / delta_p = `r`, for roughness angle i and residual angle phi_r
/// (degrees): the table, whose first point is -phi_r / i (0 when i = 0).
inline double bartonBandisMobilization(double r, double i, double phi_r) {
  const auto& x = kMobilizationDisplacement;
  const auto& y = kMobilizationRoughness;
  if (!(r < x.back())) return y.back();
  std::size_t k = 1;
  while (r >= x[k]) ++k;  // x[k-1] <= r < x[k]
  const double y0 = k == 1 ? (i > 0.0 ? -phi_r / i : 0.0) : y[k - 1];
  return y0 + (y[k] - y0) * (r - x[k - 1]) / (x[k] - x[k - 1]);
}

/// The mobilized friction angle (degrees): phi_r + m i, capped at 70 degrees.
inline double bartonBandisAngle(double phi_r, double m, double i) {
  constexpr double kMaxAngle = 70.0;
  return std::min(std::max(phi_r + m * i, 0.0), kMaxAngle);
}

/// The mobilized shear strength tau (Pa) under sigma (Pa) after the shear displacement delta (m).
inline double bartonBandisStrength(const BartonBandisScale& s, double phi_r, double sigma,
                                   double delta) {
  if (!(sigma > 0.0)) return 0.0;
  const double i = bartonBandisRoughness(s, sigma);
  const double m = i > 0.0 ? bartonBandisMobilization(delta / s.delta_p, i, phi_r) : 0.0;
  return sigma * std::tan(degToRad(bartonBandisAngle(phi_r, m, i)));
}

struct BartonBandisLaw {
  static constexpr const char* kName = "barton-bandis";
  static constexpr const char* kDescription =
      "Barton-Bandis: tau from JRC, JCS and phi_r, scale-corrected, mobilized with the shear "
      "displacement; optional dilation";
  static constexpr std::array<LawParameter, 8> kParameters{{
      CoulombLaw::kParameters[0],
      CoulombLaw::kParameters[1],
      {"jrc", ParameterUnit::kDimensionless, 0.0, 20.0, true, true, true, 0.0, nullptr,
       Reduction::kNone, "joint roughness coefficient JRC_0 at lab_length"},
      {"jcs", ParameterUnit::kPressure, 0.0, 1e300, false, true, true, 0.0, nullptr,
       Reduction::kNone, "joint wall compressive strength JCS_0 at lab_length"},
      {"residual_friction_angle", ParameterUnit::kAngle, 0.0, 90.0, true, false, true, 0.0, nullptr,
       Reduction::kNone, "residual friction angle phi_r"},
      {"lab_length", ParameterUnit::kLength, 0.0, 1e300, false, true, false, 0.1, nullptr,
       Reduction::kNone, "length L_0 at which jrc and jcs were measured"},
      {"field_length", ParameterUnit::kLength, 0.0, 1e300, true, true, false, 0.0, nullptr,
       Reduction::kNone, "joint length L_n (0: sqrt of each face contact's area)"},
      {"dilation", ParameterUnit::kFlag, 0.0, 1.0, true, true, false, 0.0, nullptr,
       Reduction::kNone, "accumulate the mobilized dilation while slipping"},
  }};
  static constexpr std::array<const char*, 2> kHistoryColumns{"shear_displacement",
                                                              "dilation_opening"};
  static constexpr bool kReducesMobilizedStrength = true;

  static void coefficients(std::span<const double> p, LawCoefficients& k) {
    k.jkn = p[0];
    k.jks = p[1];
    k.tan_friction = 0.0;
    k.cohesion = 0.0;
    k.cohesion_stress = 0.0;
    k.tensile_strength = 0.0;
    k.jrc = p[2];
    k.jcs = p[3];
    k.residual_angle = p[4];
    k.tan_residual = std::tan(degToRad(p[4]));
    k.lab_length = p[5];
    k.field_length = p[6];
    k.dilation = p[7] != 0.0;
  }

  struct Pair {
    BartonBandisScale scale;
    double area = 0.0;
  };
  static Pair prepare(const LawCoefficients& k, double area) {
    const double length = k.field_length > 0.0 ? k.field_length : std::sqrt(area);
    return {bartonBandisScale(k.jrc, k.jcs, k.lab_length, length), area};
  }
  /// The mean of the pair's sub-contacts of the last step, summed in key order.
  static void inherit(std::span<const particles::SubFeature>,
                      std::span<const particles::SubHistory> old, const contact::FaceContact&,
                      double* h) {
    h[0] = h[1] = 0.0;
    if (old.empty()) return;
    for (const auto& o : old) {
      h[0] += o.law[0];
      h[1] += o.law[1];
    }
    h[0] /= static_cast<double>(old.size());
    h[1] /= static_cast<double>(old.size());
  }
  static double effectiveGap(double gap, const double* h) { return gap + h[1]; }
  static double openGap(const double*, double) { return 0.0; }
  static double tension(const double*, double) { return 0.0; }
  static double cap(const Pair& p, const LawCoefficients& k, double, double w, double, double gap,
                    double slide, double* h) {
    h[0] += slide;
    const double tau = bartonBandisStrength(p.scale, k.residual_angle, k.jkn * gap, h[0]);
    return w * p.area * tau / k.strength_divisor;
  }
  /// With dilation: the opening grows by tan(d_mob) |v_t| dt, d_mob = 0.5 max(m, 0) i (the
  /// table's m < 0 before 0.3 delta_p raises the friction from 0 to phi_r; it is no contraction).
  static void slipped(const Pair& p, const LawCoefficients& k, double gap, double slide,
                      double* h) {
    if (!k.dilation) return;
    const double sigma = k.jkn * gap;
    const double i = bartonBandisRoughness(p.scale, sigma);
    if (!(i > 0.0)) return;
    const double m = bartonBandisMobilization(h[0] / p.scale.delta_p, i, k.residual_angle);
    if (!(m > 0.0)) return;
    h[1] += std::tan(degToRad(0.5 * m * i)) * slide;
  }
  static bool keepOpen(bool, double*) { return false; }
};

}  // namespace polydem::dynamics
