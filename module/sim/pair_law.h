// Operator 5 of the contact phase (contact_phase.h): the contact law. Turns a pair's modelled
// contact into forces on A (dynamics/contact_law.h for a single point, dynamics/sub_contact_law.h
// for sub-contacts) and appends the pair's new history, in key order, to the next step's table.
#pragma once

#include <span>
#include <vector>

#include "polydem/contact/face_contact.h"
#include "polydem/dynamics/contact_law.h"
#include "polydem/dynamics/sub_contact_law.h"
#include "polydem/particles/contact_history.h"
#include "polydem/sim/contact_model.h"

namespace polydem::sim {

/// What the law gives for one pair: the force on A (B gets minus it) and where it acts.
struct PairLawResult {
  bool touching = false;
  bool split = false;         // sub-contacts: force and torques as resultants
  Vec3 point = Vec3::Zero();  // single point: where the force acts; split: centre of pressure
  Vec3 normal = Vec3::Zero();
  Vec3 force = Vec3::Zero();                              // on A
  Vec3 torque_a = Vec3::Zero(), torque_b = Vec3::Zero();  // split only: about A's, B's
                                                          // centroids
  double normal_force = 0.0, shear_force = 0.0, energy = 0.0;
  int subcontacts = 0;  // sub-contacts in compression
};

class PairLaw {
 public:
  /// The law for pair `key` whose last history is `h` (sub-contacts: old_keys/old) with the
  /// centroids and velocities `kin` of the pair's frame, coefficients `law`, effective mass
  /// `m_eff`; appends the new history to `next`. `h` is the caller's working copy (its kernel
  /// warm start already updated) and is changed into the new history: taken by value, it was
  /// copied once more per pair.
  PairLawResult apply(const particles::PairKey& key, const ModelledContact& modelled,
                      const contact::Body& a, const contact::Body& b,
                      const dynamics::PairKinematics& kin, double m_eff, double dt,
                      const dynamics::LawCoefficients& law, particles::PairHistory& h,
                      std::span<const particles::SubKey> old_keys,
                      std::span<const particles::SubHistory> old, particles::ContactHistory& next);

 private:
  contact::FaceContactBuilder face_;
  dynamics::SubContactScratch scratch_;
};

}  // namespace polydem::sim
