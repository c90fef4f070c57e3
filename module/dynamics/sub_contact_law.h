// The contact law of a pair split into sub-contacts (contact/face/face_contact.h): every
// sub-contact has a normal spring acting in compression only, a shear spring with its own history
// and its own Coulomb limit, each carrying its weight's share of the pair's stiffness, as in 3DEC's
// sub-contacts (Cundall 1988; Hart et al. 1988).
//
// For sub-contact i with weight w_i, gap g_i (> 0: penetrating), normal n_i and relative velocity
// v_i = v_rel(p_i) (Zhao eq. 31) of A's material point over B's at its point p_i:
//
//   kn_i = w_i Kn,  ks_i = w_i Ks,  Kn = kn (N/m), or jkn * A for a face contact of area A when
//   the interaction gives a joint stiffness per area (3DEC's jkn, Pa/m); likewise Ks;
//   f_n,i = max(0, kn_i g_i - w_i 2 zeta sqrt(m_eff Kn) (v_i . n_i))   if g_i > 0, else 0;
//   f_s,i = S(R(n_i,old -> n_i) f_s,i,old) - ks_i dt (v_i - (v_i . n_i) n_i)   (Zhao eqs. 32-34),
//   |f_s,i| <= kn_i g_i tan(phi) + w_i C                                  (Zhao eq. 35 per corner);
//
// On a rock joint (a face contact whose two faces lie on one joint plane, sim/pair_law.h) the
// strengths are stresses, each sub-contact carrying its share of the area A: C = A c, and the
// normal spring may also pull, f_n,i >= -w_i A sigma_t: a corner whose gap is between
// -sigma_t / jkn and 0 keeps its springs in tension (its shear cap kn_i g_i tan(phi) + w_i A c,
// not below 0); one pulled further carries nothing this step. The plain Coulomb joint keeps its
// strengths: a corner that slipped or opened has the same c and sigma_t at the next step.
// Tension acts only while the kernel reports the pair touching: there is no bond across a gap.
//
// R is the smallest rotation of the old normal onto the new (rotateShear), S the rotation about
// n_i by the mean spin of the two bodies about it over the step, ((wA + wB) / 2 . n_i) dt: a
// shear spring is attached to both surfaces, so a pair turning together carries it along, and a
// pair twisting against each other loads the springs in opposite directions around the area,
// which resists the twist. The normal forces are the gradient of sum_i kn_i max(g_i, 0)^2 / 2,
// since each g_i is measured along the normal of the face its vertex meets: an undamped,
// frictionless contact conserves energy.
//
// History: a sub-contact in compression keeps its shear and normal under its feature key for the
// next step. A corner that opens (g_i <= 0) releases its spring. When the corners change because
// the overlap changed shape (a vertex of one body crossed an edge of the other, a point contact
// became a face), the shear of the sub-contacts that vanished is handed to the ones that appeared,
// in proportion to their weights, so the pair's stored shear force does not drop on a change of
// labels.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "polydem/contact/face/face_contact.h"
#include "polydem/dynamics/contact_law.h"
#include "polydem/particles/contact_history.h"

namespace polydem::dynamics {

/// Positions (centroids) and half-step velocities of A and B in the pair's frame.
struct PairKinematics {
  Vec3 xa = Vec3::Zero(), va = Vec3::Zero(), wa = Vec3::Zero();
  Vec3 xb = Vec3::Zero(), vb = Vec3::Zero(), wb = Vec3::Zero();
};

/// What the law returns for one pair.
struct PairForce {
  Vec3 force = Vec3::Zero();     // on A, the sum over sub-contacts
  Vec3 torque_a = Vec3::Zero();  // about A's centroid
  Vec3 torque_b = Vec3::Zero();  // of the forces on B (minus A's), about B's centroid
  Vec3 centre = Vec3::Zero();    // centre of pressure: normal-force weighted mean of the points
  double normal = 0.0;           // sum of the normal forces, N
  double shear = 0.0;            // |sum of the shear forces|, N
  double energy = 0.0;           // spring energy: kn_i g_i^2 / 2 + |f_s,i|^2 / (2 ks_i), J
  int loaded = 0;                // sub-contacts in compression
  int kept = 0;  // sub-contacts whose history is kept: those in compression and those the joint
                 // law keeps open (coulomb-residual's broken ones)
  bool sliding = false;  // some sub-contact reached its Coulomb limit
};

/// Working space of subContactForces, one entry per sub-contact, kept by the caller between
/// pairs so that the law allocates nothing once warm.
struct SubContactScratch {
  std::vector<Vec3> carried;         // the shear a sub-contact brings into the step
  std::vector<std::uint8_t> origin;  // where that shear comes from (sub_contact_law.cpp)
  // Joint laws with history: each sub-contact's values, and whether it had a history entry.
  std::vector<std::array<double, particles::kMaxLawHistory>> state;
  std::vector<std::uint8_t> had_history;
};

/// Advances the sub-contacts `fc` of one touching pair by one step, by the joint law k.law
/// (dynamics/joint_law.h). `old_keys`/`old` are the pair's sub-contact histories of the last step
/// (sorted by feature); the sub-contacts in compression and those the law keeps open,
/// PairForce::kept of them, are written in key order to the first slots of `kept`
/// (features and histories; the pair's keys are the caller's), to be stored for the next step.
/// Pre: as contactForce(); fc.subs sorted by feature, weights summing to 1; `kept` has
/// fc.subs.size() slots.
PairForce subContactForces(const contact::FaceContact& fc,
                           std::span<const particles::SubFeature> old_keys,
                           std::span<const particles::SubHistory> old, const PairKinematics& kin,
                           double m_eff, double dt, const LawCoefficients& k,
                           const particles::SubSlots& kept, SubContactScratch& scratch);

/// The same, the kept sub-contacts in `kept`, with working space of its own (allocates; for a
/// single pair).
PairForce subContactForces(const contact::FaceContact& fc,
                           std::span<const particles::SubFeature> old_keys,
                           std::span<const particles::SubHistory> old, const PairKinematics& kin,
                           double m_eff, double dt, const LawCoefficients& k,
                           std::vector<particles::SubEntry>& kept);

/// `shear` (tangent to n) turned about the unit normal n by the angle 2 atan(t): the Cayley
/// form ((1 - t^2) s + 2 t n x s) / (1 + t^2), exactly a rotation without trigonometry; for the
/// small angles of one step, t = angle / 2 to third order. Inline: called for every sub-contact.
inline Vec3 spinShear(const Vec3& shear, const Vec3& n, double t) {
  const double tt = t * t;
  return ((1.0 - tt) * shear + (2.0 * t) * n.cross(shear)) / (1.0 + tt);
}

}  // namespace polydem::dynamics
