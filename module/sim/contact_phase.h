// The contact phase of a step: candidate pairs from the broad phase -> kernel -> contact law ->
// forces and torques summed per particle.
//
// Determinism across rank counts rests on three rules applied here:
//  1. every pair is evaluated in one canonical frame, that of its lower-uid particle A: A at its
//     stored position, B at its stored position plus the difference of the two periodic image
//     shifts. Ghosts carry the owner's bits, so every rank that evaluates a pair feeds the kernel
//     identical numbers and gets identical forces, histories and warm starts;
//  2. the decision whether a pair is evaluated at all (bounding spheres, then boxes) is made here,
//     in that frame, not by the broad phase (which only has to return a superset);
//  3. pairs are visited in key order (lo uid, hi uid) and each particle's force is accumulated in
//     that order, which is the order of its partners' uids.
#pragma once

#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include "polydem/broadphase/broad_phase.h"
#include "polydem/contact/contact.h"
#include "polydem/contact/face_contact.h"
#include "polydem/contact/overlap_point.h"
#include "polydem/dynamics/contact_law.h"
#include "polydem/dynamics/monitors.h"
#include "polydem/dynamics/sub_contact_law.h"
#include "polydem/setup/setup.h"
#include "polydem/particles/contact_history.h"
#include "polydem/particles/particle_storage.h"

namespace polydem::sim {

/// Everything the contact phase needs besides the particles.
struct ContactSetup {
  const particles::ShapeTable* shapes = nullptr;
  const contact::Kernel* kernel = nullptr;
  // Law coefficients per material pair (index a * materials + b) for the current stage.
  const std::vector<dynamics::LawCoefficients>* law = nullptr;
  int materials = 0;
  const std::vector<io::DriverSpec>* drivers = nullptr;
  // Split penalty contacts into sub-contacts at the corners of the face overlap
  // (contact/face_contact.h, dynamics/sub_contact_law.h); false: the single-point model.
  bool sub_contacts = true;
  // Move each touching contact's point to the centroid of the overlap volume (overlap_point.h;
  // single-point model only).
  bool overlap_centroid = false;
  double margin = 0.0;  // absolute: pairs with centroid distance <= rA + rB + margin are evaluated
  double dt = 0.0;
  double time = 0.0;  // t_n: forces are computed at t_n with velocities at t_n - dt/2
};

/// One evaluated pair, kept for output and monitors.
struct ContactRecord {
  particles::PairKey key;
  std::int32_t a = -1, b = -1;  // local indices of A and B when local and free, else -1
  std::int32_t stored_a = -1, stored_b = -1;  // storage indices of A and B (ghosts included)
  bool touching = false;
  Vec3 point = Vec3::Zero();  // in A's frame (the world frame unless A is a periodic image); with
                              // sub-contacts the centre of pressure
  Vec3 normal = Vec3::Zero();
  Vec3 force = Vec3::Zero();  // on A
  double normal_force = 0.0, shear_force = 0.0;
  double energy = 0.0;  // elastic energy of the normal springs (penalty contacts), J
  contact::Status status = contact::Status::kOk;
  std::int32_t subcontacts = 0;  // sub-contacts in compression (0 for the single-point model)
  bool a_is_local = false;       // A is stored on this rank as a local particle
  bool both_free = false;        // neither A nor B is fixed or driven
};

struct ContactPhaseStats {
  std::int64_t candidates = 0;  // pairs from the broad phase
  std::int64_t evaluated = 0;   // pairs passing the sphere and box tests (kernel calls)
  std::int64_t touching = 0;
  std::int64_t subcontacts = 0;  // sub-contacts in compression (sub-contact model)
  std::int64_t not_converged = 0, degenerate = 0, inner_domain = 0;
};

class ContactPhase {
 public:
  /// Evaluates all pairs of `candidates` (broad-phase output over `storage`), replaces `history`
  /// by the histories of the evaluated pairs, and leaves in `forces` (parallel to storage) the
  /// contact forces and torques on local free particles, summed in partner-uid order.
  ContactPhaseStats run(const ContactSetup& setup, const particles::ParticleStorage& storage,
                        std::span<const broadphase::CandidatePair> candidates,
                        particles::ContactHistory& history,
                        std::vector<dynamics::ForceAccumulator>& forces);

  const std::vector<ContactRecord>& records() const { return records_; }

 private:
  struct Candidate {
    particles::PairKey key;
    std::int32_t a, b;  // storage indices of the lower- and higher-uid particle
  };
  void sortCandidates(const particles::ParticleStorage& storage,
                      std::span<const broadphase::CandidatePair> candidates);

  std::vector<Candidate> candidates_;
  std::vector<std::pair<Uid, std::int32_t>> by_uid_;  // (uid, storage index), sorted
  std::vector<std::int32_t> uid_rank_;                // per storage index: rank of its uid
  std::vector<std::size_t> bucket_start_, fill_;      // candidates per lower-uid rank
  std::vector<Vec3> box_lo_, box_hi_;                 // per storage index, this step
  std::vector<ContactRecord> records_;
  particles::ContactHistory next_;
  std::vector<Vec3> scratch_a_, scratch_b_;
  contact::OverlapCentroid overlap_;
  contact::FaceContactBuilder face_;
  std::vector<dynamics::SubState> kept_;
};

}  // namespace polydem::sim
