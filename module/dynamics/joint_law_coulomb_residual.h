// The joint law `coulomb-residual` (3DEC's Coulomb slip with residual strength, Itasca 3DEC
// manual, "Joint constitutive models"): a sub-contact is intact, tau_max = c + sigma tan(phi) and
// tension up to sigma_t, until it slips (its shear exceeds its cap) or opens in tension beyond
// sigma_t (its gap falls to -sigma_t / jkn or below; with sigma_t = 0, as soon as it opens). From
// then on it is broken for good: c = 0, sigma_t = 0, tau_max = sigma tan(phi_r).
//
// History, one value per sub-contact: `broken` (0 or 1). A broken sub-contact that opens keeps
// its history (zero shear) while its pair touches, so that it stays broken when it closes again.
// A sub-contact that appears in a pair (no history of its own) is broken if any sub-contact of the
// pair that vanished this step, whose shear it takes over, was broken. A pair that stops touching
// altogether forgets its sub-contacts, as 3DEC deletes a contact whose blocks separate.
#pragma once

#include "polydem/dynamics/joint_law_coulomb.h"

namespace polydem::dynamics {

struct CoulombResidualLaw {
  static constexpr const char* kName = "coulomb-residual";
  static constexpr const char* kDescription =
      "Coulomb slip with residual strength: a sub-contact that slips or opens loses c and "
      "sigma_t for good and takes phi_r";
  static constexpr std::array<LawParameter, 6> kParameters{{
      CoulombLaw::kParameters[0],
      CoulombLaw::kParameters[1],
      CoulombLaw::kParameters[2],
      CoulombLaw::kParameters[3],
      CoulombLaw::kParameters[4],
      {"residual_friction_angle", ParameterUnit::kAngle, 0.0, 90.0, true, false, false, 0.0,
       "friction_angle", Reduction::kTangent, "friction angle phi_r once broken"},
  }};
  static constexpr std::array<const char*, 1> kHistoryColumns{"broken"};
  static constexpr bool kReducesMobilizedStrength = false;

  static void coefficients(std::span<const double> p, LawCoefficients& k) {
    CoulombLaw::coefficients(p, k);
    k.tan_residual = std::tan(degToRad(p[5]));
  }

  struct Pair {};
  static Pair prepare(const LawCoefficients&, double) { return {}; }
  /// Broken if a vanished sub-contact of the pair (an old key no new one has) was broken.
  static void inherit(std::span<const particles::SubFeature> old_keys,
                      std::span<const particles::SubHistory> old, const contact::FaceContact& fc,
                      double* h) {
    std::size_t i = 0;
    h[0] = 0.0;
    for (std::size_t j = 0; j < old_keys.size(); ++j) {
      while (i < fc.subs.size() && fc.subs[i].feature < old_keys[j].feature) ++i;
      const bool kept = i < fc.subs.size() && fc.subs[i].feature == old_keys[j].feature;
      if (!kept && old[j].law[0] != 0.0) h[0] = 1.0;
    }
  }
  static double effectiveGap(double gap, const double*) { return gap; }
  static double openGap(const double* h, double open_gap) { return h[0] != 0.0 ? 0.0 : open_gap; }
  static double tension(const double* h, double tension) { return h[0] != 0.0 ? 0.0 : tension; }
  static double cap(const Pair&, const LawCoefficients& k, double f_elastic, double w,
                    double cohesion, double, double, double* h) {
    if (h[0] != 0.0) return std::max(f_elastic * k.tan_residual, 0.0);
    return std::max(f_elastic * k.tan_friction + w * cohesion, 0.0);
  }
  static void slipped(const Pair&, const LawCoefficients&, double, double, double* h) {
    h[0] = 1.0;
  }
  /// An opened sub-contact that had a bond (a history) or was broken stays, broken.
  static bool keepOpen(bool had_history, double* h) {
    if (!had_history && h[0] == 0.0) return false;
    h[0] = 1.0;
    return true;
  }
};

}  // namespace polydem::dynamics
