#include "polydem/dynamics/contact_law.h"

#include <algorithm>
#include <cmath>

#include "polydem/core/error.h"
#include "polydem/core/strings.h"

namespace polydem::dynamics {

LawCoefficients lawCoefficients(const particles::ContactProperties& p,
                                std::optional<double> friction_angle_deg) {
  const double phi = friction_angle_deg.value_or(p.friction_angle);
  if (!(phi >= 0.0 && phi < 90.0)) {
    throw Error(cat("contact law: friction angle ", phi, " deg is outside [0, 90)"));
  }
  if (!(p.kn >= 0.0 && p.ks >= 0.0 && p.penalty >= 0.0)) {
    throw Error(cat("contact law: stiffnesses must be >= 0 (kn ", p.kn, ", ks ", p.ks, ", penalty ",
                    p.penalty, ")"));
  }
  if (!(p.jkn >= 0.0 && p.jks >= 0.0)) {
    throw Error(
        cat("contact law: joint stiffnesses must be >= 0 (jkn ", p.jkn, ", jks ", p.jks, ")"));
  }
  if (!(p.cohesion >= 0.0 && p.normal_damping >= 0.0)) {
    throw Error(cat("contact law: cohesion (", p.cohesion, ") and normal damping (",
                    p.normal_damping, ") must be >= 0"));
  }
  LawCoefficients k;
  k.kn = p.kn;
  k.ks = p.ks;
  k.penalty = p.penalty;
  k.tan_friction = std::tan(degToRad(phi));
  k.cohesion = p.cohesion;
  k.damping_ratio = p.normal_damping;
  k.jkn = p.jkn;
  k.jks = p.jks;
  return k;
}

void resetShear(particles::PairHistory& history) {
  history.shear_force.setZero();
  history.normal.setZero();
  history.touching = 0;
}

ContactForce contactForce(const contact::Contact& c, const Vec3& v_rel, double m_eff, double dt,
                          const LawCoefficients& k, particles::PairHistory& history) {
  ContactForce out;
  if (!c.touching) {
    resetShear(history);
    return out;
  }
  const Vec3& n = c.normal;

  // Normal force: elastic part, then viscous damping on the normal relative velocity.
  double f_elastic = 0.0;
  double k_eff = 0.0;
  if (c.model == contact::ForceModel::kPenalty) {
    f_elastic = k.kn * c.depth;
    k_eff = k.kn;
  } else {
    f_elastic = k.penalty * c.potential;  // Zhao eq. 13
    k_eff = c.depth > 0.0 ? f_elastic / c.depth : 0.0;
  }
  f_elastic = std::max(f_elastic, 0.0);
  const double v_normal = v_rel.dot(n);  // > 0: A moves away from B
  double f_normal = f_elastic;
  if (k.damping_ratio > 0.0 && k_eff > 0.0) {
    f_normal -= 2.0 * k.damping_ratio * std::sqrt(m_eff * k_eff) * v_normal;
  }
  f_normal = std::max(f_normal, 0.0);  // no tension

  // Shear force: last step's shear carried onto the new plane (Zhao eq. 33), plus the increment
  // of the tangential relative displacement (eqs. 32, 34). The sign makes it oppose A's motion.
  const bool continuing = history.touching != 0 && history.normal.squaredNorm() > 0.0;
  Vec3 shear = continuing ? rotateShear(history.shear_force, history.normal, n) : Vec3::Zero();
  const Vec3 v_tangent = v_rel - v_normal * n;
  shear -= (k.ks * dt) * v_tangent;

  // Coulomb cap with cohesion (Zhao eq. 35), on the elastic normal force: the dashpot carries no
  // friction (as in the linear contact model of PFC).
  const double cap = f_elastic * k.tan_friction + k.cohesion;
  double magnitude = shear.norm();
  if (magnitude > cap) {
    shear *= cap / magnitude;  // magnitude > cap >= 0
    magnitude = cap;
    out.sliding = true;
  }

  history.shear_force = shear;
  history.normal = n;
  history.touching = 1;

  out.force = f_normal * n + shear;
  out.normal = f_normal;
  out.normal_elastic = f_elastic;
  out.shear = magnitude;
  return out;
}

}  // namespace polydem::dynamics
