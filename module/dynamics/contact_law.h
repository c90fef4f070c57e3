// The contact law: from the geometry of one contact (contact/contact.h) and the pair's history to
// the force on particle A. Normal spring (penalty or distance potential) with optional viscous
// damping, incremental tangential spring rotated with the contact plane, Coulomb cap with cohesion.
//
// Conventions (the same as contact/contact.h and BENCHMARKS.md section C):
//   - the pair is (A, B) with A the lower uid; `Contact::normal` n is the unit vector from B into
//   A;
//   - v_rel is the velocity of A's material point at the contact point relative to B's:
//       v_rel = (vA + wA x (p - xA)) - (vB + wB x (p - xB))          (Zhao eq. 31)
//     with the leapfrog half-step velocities (t - dt/2); relativeVelocity() below computes it;
//   - the returned force acts on A at `Contact::point`; B receives minus it at the same point;
//     torques are (p - x) x F (Zhao eq. 36), see contactTorque();
//   - the stored shear force (PairHistory::shear_force) is the tangential force on A, world frame.
// Units: SI. kn, ks in N/m; penalty in Pa; Contact::potential in m^2; cohesion in N.
//
// The functions here run once per contact per step: they allocate nothing, hold no state of their
// own and give the same bits for the same inputs.
#pragma once

#include <cstdint>
#include <optional>

#include "polydem/contact/contact.h"
#include "polydem/core/types.h"
#include "polydem/particles/contact_history.h"
#include "polydem/particles/material.h"

namespace polydem::dynamics {

/// The law of a joint (dynamics/joint_law.h): one enumerator per line of joint_law_list.inc.
enum class JointLaw : std::uint8_t {
#define POLYDEM_JOINT_LAW(id, type) id,
#include "polydem/dynamics/joint_law_list.inc"
#undef POLYDEM_JOINT_LAW
};

/// The coefficients of the law for one pair of materials in one stage, ready for the hot loop
/// (the friction angle is turned into its tangent once). Build one per material pair and stage.
struct LawCoefficients {
  double kn = 0.0;             // N/m, normal spring of kPenalty contacts
  double ks = 0.0;             // N/m, tangential spring
  double penalty = 0.0;        // Pa, normal penalty of kPotential contacts (Zhao eq. 13)
  double tan_friction = 0.0;   // tan(phi) of Zhao eq. 35
  double cohesion = 0.0;       // N, the C of Zhao eq. 35
  double damping_ratio = 0.0;  // zeta: viscous normal damping as a fraction of critical
  double jkn = 0.0;            // Pa/m: sub-contact model, face contacts (0: kn per pair)
  double jks = 0.0;            // Pa/m: likewise for the shear spring (0: ks per pair)
  // A joint's strengths as stresses (sub-contact model, face contacts): each sub-contact of
  // weight w of a face contact of area A adds w A cohesion_stress to its shear cap and may pull
  // up to w A tensile_strength (dynamics/sub_contact_law.h). 0 for material pairs.
  double cohesion_stress = 0.0;   // Pa
  double tensile_strength = 0.0;  // Pa
  // The joint's law (material pairs: kCoulomb) and the parameters of the laws beyond Coulomb's
  // (dynamics/joint_law_*.h), ready for the hot loop.
  JointLaw law = JointLaw::kCoulomb;
  double tan_residual = 0.0;      // tan(phi_r): coulomb-residual, barton-bandis
  double residual_angle = 0.0;    // phi_r, degrees: barton-bandis
  double jrc = 0.0;               // JRC_0: barton-bandis
  double jcs = 0.0;               // JCS_0, Pa: barton-bandis
  double lab_length = 0.0;        // L_0, m: barton-bandis
  double field_length = 0.0;      // L_n, m (0: sqrt of the face contact's area): barton-bandis
  bool dilation = false;          // barton-bandis: accumulate the mobilized dilation
  double strength_divisor = 1.0;  // barton-bandis under strength reduction: tau / F
};

/// Coefficients from a pair's properties. `friction_angle_deg`, when given, replaces the pair's
/// friction angle (the initial-equilibrium stage of Keissar section 3.3 uses 89 degrees).
/// Throws polydem::Error for a friction angle outside [0, 90) degrees or a negative stiffness,
/// penalty, cohesion or damping ratio.
LawCoefficients lawCoefficients(const particles::ContactProperties& properties,
                                std::optional<double> friction_angle_deg = std::nullopt);

/// What the law returns for one contact.
struct ContactForce {
  Vec3 force = Vec3::Zero();  // total force on A (normal + shear), world frame, acting at the point
  double normal = 0.0;        // normal force: elastic + viscous, clamped to >= 0 (N)
  double normal_elastic = 0.0;  // elastic part alone (N); the Coulomb cap uses this one
  double shear = 0.0;           // |shear force| after the cap (N)
  bool sliding = false;         // the Coulomb cap was reached this step
};

/// The force on A for one contact, and the pair's history advanced by one step. A contact that is
/// not touching (c.touching false) gives a zero force and resetShear(history).
///
/// Pre:  c.normal is a unit vector from B into A; c.depth >= 0 (kPenalty) or
///       c.potential >= 0 (kPotential); dt > 0; m_eff > 0 (mA mB / (mA + mB), or mA when B is
///       fixed or driven); `history` is this pair's entry (a default PairHistory for a new pair).
/// Post (touching): history.shear_force is the new shear force on A (tangent to c.normal,
///       |.| <= cap); history.normal == c.normal; history.touching == 1. history.kernel is never
///       touched.
///
/// Normal force (Zhao eq. 13 for kPotential):
///   f_el = kn depth (kPenalty)   or   penalty * potential (kPotential),
///   f_n  = max(0, f_el - 2 zeta sqrt(m_eff k_eff) (v_rel . n)),
/// with k_eff = kn for kPenalty and the secant stiffness f_el / depth for kPotential (the tangent
/// stiffness of the potential is not known from one contact; the secant equals it for face
/// contacts, where the potential grows linearly with depth; no damping if depth is 0). The normal
/// force never pulls.
/// Shear force (Zhao eqs. 32-35), tangential velocity v_t = v_rel - (v_rel . n) n:
///   f_s = rotateShear(f_s_old, n_old, n) - ks dt v_t,   |f_s| <= f_el tan(phi) + C,
/// the shear is scaled back onto the cap when it exceeds it (then `sliding`). The shear on A
/// opposes A's tangential motion relative to B. A pair that was not touching at the previous step
/// (history.touching == 0 or no stored normal) starts from a zero shear force.
ContactForce contactForce(const contact::Contact& c, const Vec3& v_rel, double m_eff, double dt,
                          const LawCoefficients& k, particles::PairHistory& history);

/// For a pair that is not touching this step: shear force and stored normal cleared, touching = 0.
/// The kernel's warm start (history.kernel) is kept: it stays useful while the pair is close.
/// A later contact of the pair then starts afresh (zero shear, no rotation from an old plane).
void resetShear(particles::PairHistory& history);

/// The shear force carried from the contact plane of normal `n_old` onto that of `n_new`: the
/// rotation R that takes n_old to n_new by the smallest angle (Zhao eq. 33), applied to `shear`.
/// Built as two reflections, R = H(n_new) H(m) with m the bisector of n_old and n_new, so it needs
/// no trigonometry and no cross product. For exactly opposite normals the smallest rotation is not
/// unique: the half turn about the shear's own direction is taken, which leaves the shear as it is.
/// The result is projected onto the plane normal to n_new (so that round-off does not accumulate a
/// normal component over many steps). Pre: n_old and n_new are unit vectors; shear is tangent to
/// n_old. Post: |result| == |shear| and result . n_new == 0, both to round-off.
/// Inline: the sub-contact law calls it for every sub-contact of every pair.
inline Vec3 rotateShear(const Vec3& shear, const Vec3& n_old, const Vec3& n_new) {
  // The smallest rotation taking n_old to n_new is H(n_new) H(m), the product of the reflections
  // through the planes normal to the bisector m = s / |s|, s = n_old + n_new, and to n_new. H(m)
  // maps the plane normal to n_old onto the plane normal to n_new, where H(n_new) is the identity;
  // so on a tangent vector the rotation is the single reflection H(m) = I - 2 s s^T / (s . s).
  // s . s = 2 (1 + cos angle) is computed from s itself, accurate close to the half turn.
  const Vec3 s = n_old + n_new;
  const double ss = s.squaredNorm();
  // Opposite normals to within 1e-10 rad (s . s ~ angle^2): no unique smallest rotation; the half
  // turn about the shear's own direction keeps the shear unchanged.
  constexpr double kOpposite = 1e-20;
  Vec3 rotated = shear;
  if (ss > kOpposite) rotated -= (2.0 * shear.dot(s) / ss) * s;
  return rotated - rotated.dot(n_new) * n_new;
}

/// Velocity of A's material point at `point` relative to B's (Zhao eq. 31).
inline Vec3 relativeVelocity(const Vec3& point, const Vec3& xa, const Vec3& va, const Vec3& wa,
                             const Vec3& xb, const Vec3& vb, const Vec3& wb) {
  return (va + wa.cross(point - xa)) - (vb + wb.cross(point - xb));
}

/// Torque about `centroid` of `force` acting at `point` (Zhao eq. 36 for the shear part).
inline Vec3 contactTorque(const Vec3& point, const Vec3& centroid, const Vec3& force) {
  return (point - centroid).cross(force);
}

}  // namespace polydem::dynamics
