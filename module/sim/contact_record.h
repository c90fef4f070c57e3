// Operator 6 of the contact phase (contact_phase.h): recording. Per evaluated pair, in key order:
// a small work entry, every step, for the load model and the contact count of the monitors; and,
// when a reader asks for them (ContactPhase::keepRecords), a full record for output, tracked
// particles and checks. Also the phase's counts.
#pragma once

#include <cstdint>

#include "polydem/contact/contact.h"
#include "polydem/core/types.h"
#include "polydem/particles/contact_history.h"

namespace polydem::sim {

/// One evaluated pair as the load model (load_balance.h) and the contact count (global_monitors.h)
/// read it on every step: its storage indices, its sub-contacts in compression and four flags.
struct PairWork {
  enum Flag : std::uint8_t {
    kTouching = 1,  // the kernel found the pair touching
    kAFree = 2,     // A is local and free (ContactRecord::a >= 0)
    kBFree = 4,     // B is local and free (ContactRecord::b >= 0)
    kALocal = 8,    // A is stored on this rank as a local particle
  };
  std::int32_t stored_a = -1, stored_b = -1;  // storage indices of A and B (ghosts included)
  std::uint16_t subcontacts = 0;  // in compression, saturated at 65535 (a face pair has far fewer)
  std::uint8_t flags = 0;
  bool has(Flag f) const { return (flags & f) != 0; }
};

/// One evaluated pair, kept for output, tracked particles and checks.
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
  std::int32_t joint = -1;       // the [[joint]] whose properties it took, -1: the material pair's
  bool a_is_local = false;       // A is stored on this rank as a local particle
  bool both_free = false;        // neither A nor B is fixed or driven
};

struct ContactPhaseStats {
  std::int64_t candidates = 0;  // pairs from the broad phase
  std::int64_t evaluated = 0;   // pairs passing the sphere and box tests (kernel calls)
  std::int64_t early = 0;       // of those: evaluated while the exchange was in flight
  std::int64_t touching = 0;
  std::int64_t subcontacts = 0;  // sub-contacts in compression (sub-contact model)
  std::int64_t not_converged = 0, degenerate = 0, inner_domain = 0;
};

/// Counts one evaluated pair's kernel status.
inline void countStatus(ContactPhaseStats& stats, contact::Status status) {
  stats.not_converged += status == contact::Status::kNotConverged;
  stats.degenerate += status == contact::Status::kDegenerate;
  stats.inner_domain += status == contact::Status::kInnerDomainReached;
}

}  // namespace polydem::sim
