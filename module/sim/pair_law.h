// Operator 5 of the contact phase (contact_phase.h): the contact law. Turns a pair's modelled
// contact into forces on A (dynamics/contact_law.h for a single point, dynamics/sub_contact_law.h
// for sub-contacts) and writes the pair's new history into its entry of the next step's table.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "polydem/contact/face/face_contact.h"
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
  int joint = -1;       // the joint whose properties the pair took, -1: the material pair's
};

/// Which joint a pair's face contact lies on (docs/scene-format.md, "Joints"): a face contact
/// whose facing faces lie on the same joint plane takes that plane's joint, if it has one;
/// everything else (corner and edge contacts, faces of two different planes, faces of no plane)
/// the material pair's properties.
struct PairJoints {
  std::span<const std::int32_t> face_plane_a, face_plane_b;  // the two shapes' face planes
  std::span<const std::int32_t> plane_joint;                 // joint plane -> joint, -1: none
  // Coefficients per joint and material pair: index (joint * materials + a) * materials + b.
  std::span<const dynamics::LawCoefficients> law;
  int materials = 0, material_a = 0, material_b = 0;

  /// The joint of a face contact between faces `fa` of A and `fb` of B, or -1.
  int jointOf(int fa, int fb) const {
    if (face_plane_a.empty() || face_plane_b.empty()) return -1;
    const std::int32_t plane = face_plane_a[static_cast<std::size_t>(fa)];
    if (plane < 0 || plane != face_plane_b[static_cast<std::size_t>(fb)]) return -1;
    return plane_joint[static_cast<std::size_t>(plane)];
  }
  const dynamics::LawCoefficients& coefficients(int joint) const {
    return law[static_cast<std::size_t>((joint * materials + material_a) * materials + material_b)];
  }
};

class PairLaw {
 public:
  /// The law for a pair with the centroids and velocities `kin` of its frame, coefficients
  /// `law` (or those of the pair's joint, `joints`), effective mass `m_eff`. `h` is the pair's
  /// entry, appended last to `next` by the caller with last step's history (sub-contacts:
  /// old_keys/old) and the kernel's new warm start; the law turns it into the new history in place
  /// and appends the pair's sub-contacts to `next`.
  PairLawResult apply(const ModelledContact& modelled, const contact::Body& a,
                      const contact::Body& b, const dynamics::PairKinematics& kin, double m_eff,
                      double dt, const dynamics::LawCoefficients& law, const PairJoints& joints,
                      particles::PairHistory& h, std::span<const particles::SubFeature> old_keys,
                      std::span<const particles::SubHistory> old, particles::ContactHistory& next);

 private:
  contact::FaceContactBuilder face_;
  dynamics::SubContactScratch scratch_;
};

}  // namespace polydem::sim
