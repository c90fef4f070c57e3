#include "polydem/sim/pair_law.h"

namespace polydem::sim {

PairLawResult PairLaw::apply(const ModelledContact& modelled, const contact::Body& a,
                             const contact::Body& b, const dynamics::PairKinematics& kin,
                             double m_eff, double dt, const dynamics::LawCoefficients& law,
                             const PairJoints& joints, particles::PairHistory& h,
                             std::span<const particles::SubFeature> old_keys,
                             std::span<const particles::SubHistory> old,
                             particles::ContactHistory& next) {
  const contact::Contact& contact = modelled.contact;
  PairLawResult r;
  if (modelled.split && contact.touching) {
    // Sub-contacts: a spring at every corner of the face overlap, each with its own history.
    const auto fc = face_.build(a, b, contact);
    // A face contact on one joint plane takes the joint's coefficients (two lookups a pair).
    const int joint =
        fc.kind == contact::ContactArea::kFace ? joints.jointOf(fc.face_a, fc.face_b) : -1;
    const dynamics::LawCoefficients& k = joint >= 0 ? joints.coefficients(joint) : law;
    h.shear_force.setZero();
    h.normal = contact.normal;
    h.touching = 1;
    // The law writes the sub-contacts it keeps straight into the next step's table.
    const auto f = dynamics::subContactForces(fc, old_keys, old, kin, m_eff, dt, k,
                                              next.openSubs(fc.subs.size()), scratch_);
    next.closeSubs(static_cast<std::size_t>(f.kept));
    r.touching = true;
    r.split = true;
    r.point = f.centre;
    r.normal = contact.normal;
    r.force = f.force;
    r.torque_a = f.torque_a;
    r.torque_b = f.torque_b;
    r.normal_force = f.normal;
    r.shear_force = f.shear;
    r.subcontacts = f.loaded;
    r.energy = f.energy;
    r.joint = joint;
    return r;
  }
  const Vec3 v_rel = contact.touching ? dynamics::relativeVelocity(contact.point, kin.xa, kin.va,
                                                                   kin.wa, kin.xb, kin.vb, kin.wb)
                                      : Vec3::Zero();
  const auto f = dynamics::contactForce(contact, v_rel, m_eff, dt, law, h);
  if (!contact.touching) return r;
  r.touching = true;
  r.point = contact.point;
  r.normal = contact.normal;
  r.force = f.force;
  r.normal_force = f.normal;
  r.shear_force = f.shear;
  if (contact.model == contact::ForceModel::kPenalty) {
    r.energy = 0.5 * f.normal_elastic * contact.depth;
  }
  return r;
}

}  // namespace polydem::sim
