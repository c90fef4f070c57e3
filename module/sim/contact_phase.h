// The contact phase of a step, composed of small named operators, each in its own file:
//
//   pair_order     candidate pairs -> canonical (lower uid first), in key order
//   pair_filter    bounding spheres, then boxes, in the pair's canonical frame
//   contact_model  the kernel call and the contact model (sub-contacts / point / overlap centroid)
//   pair_law       the contact law: forces and the pair's next history
//   force_sum      the forces onto the local free particles, in partner-uid order
//   contact_record one record per evaluated pair, and the counts
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
//
// With several ranks the phase can start early (runEarly): while the exchange's messages travel,
// the pairs of two local particles present before the exchange (neither a ghost, an arrival nor a
// driven body) are evaluated into a buffer, histories included, without summing anything. run()
// then walks all pairs in key order as always, takes each buffered pair's result where it would
// have computed it, and sums forces and appends histories in that one order: the same bits.
#pragma once

#include <span>
#include <vector>

#include "polydem/broadphase/broad_phase.h"
#include "polydem/contact/contact.h"
#include "polydem/dynamics/contact_law.h"
#include "polydem/dynamics/contact_models.h"
#include "polydem/dynamics/monitors.h"
#include "polydem/particles/contact_history.h"
#include "polydem/particles/particle_storage.h"
#include "polydem/setup/setup.h"
#include "polydem/sim/contact_model.h"
#include "polydem/sim/contact_record.h"
#include "polydem/sim/pair_filter.h"
#include "polydem/sim/pair_law.h"
#include "polydem/sim/pair_order.h"

namespace polydem::sim {

/// Everything the contact phase needs besides the particles.
struct ContactSetup {
  friend bool operator==(const ContactSetup&, const ContactSetup&) = default;
  const particles::ShapeTable* shapes = nullptr;
  const contact::Kernel* kernel = nullptr;
  // Law coefficients per material pair (index a * materials + b) for the current stage.
  const std::vector<dynamics::LawCoefficients>* law = nullptr;
  int materials = 0;
  // The joints (sim/pair_law.h PairJoints): joint plane -> joint, and coefficients per joint and
  // material pair for the current stage; empty without joints.
  const std::vector<std::int32_t>* plane_joint = nullptr;
  const std::vector<dynamics::LawCoefficients>* joint_law = nullptr;
  const std::vector<dynamics::DriverSpec>* drivers = nullptr;
  // How contacts become forces (dynamics/contact_models.h).
  dynamics::ContactModel model = dynamics::ContactModel::kSubContacts;
  // Move each touching contact's point to the centroid of the overlap volume (overlap_point.h;
  // single-point model only).
  bool overlap_centroid = false;
  double margin = 0.0;  // absolute: pairs with centroid distance <= rA + rB + margin are evaluated
  double dt = 0.0;
  double time = 0.0;  // t_n: forces are computed at t_n with velocities at t_n - dt/2
};

class ContactPhase {
 public:
  /// Evaluates all pairs of `candidates` (broad-phase output over `storage`), replaces `history`
  /// by the histories of the evaluated pairs (rebuilt in place: one copy is held), and leaves in
  /// `forces` (parallel to storage) the contact forces and torques on local free particles, summed
  /// in partner-uid order.
  ContactPhaseStats run(const ContactSetup& setup, const particles::ParticleStorage& storage,
                        std::span<const broadphase::CandidatePair> candidates,
                        particles::ContactHistory& history,
                        std::vector<dynamics::ForceAccumulator>& forces);

  /// Evaluates ahead of run() the pairs of `candidates` (over `storage`, which holds local
  /// particles only) with neither member driven (a driven body's velocity depends on the time,
  /// which the next step has not reached yet), reading `history`. The results wait for the next
  /// run() with the same setup (the time aside), which uses them if the particles' states and the
  /// histories of those pairs are unchanged by then: the caller's promise (Simulation discards
  /// them otherwise). They are values matched by pair key, so a reordering of the storage in
  /// between (Simulation::sortParticles) leaves them valid. Returns the pairs evaluated.
  std::int64_t runEarly(const ContactSetup& setup, const particles::ParticleStorage& storage,
                        std::span<const broadphase::CandidatePair> candidates,
                        const particles::ContactHistory& history);
  /// Forgets what runEarly() evaluated (the state it was computed from changed).
  void discardEarly() {
    early_.clear();
    early_history_.clear();
  }

  /// Every evaluated pair of the last run(), in key order (load model, contact count).
  const std::vector<PairWork>& work() const { return work_; }
  /// The full record of every evaluated pair of the last run(), in key order, while records are
  /// kept (the default). Throws polydem::Error when they are not: a reader the run did not
  /// declare (run's readsContactRecords, Check::readsContacts) must fail, not read no contacts.
  const std::vector<ContactRecord>& records() const {
    if (!keep_records_) refuseRecords();
    return records_;
  }
  /// Whether run() keeps full records: a run whose output, tracked particles and checks read none
  /// turns them off, which gives their room back (about a tenth of a dense pack's memory).
  void keepRecords(bool keep);
  bool keepsRecords() const { return keep_records_; }

  /// Heap bytes it holds between steps (capacities, core/memory.h), by structure.
  struct Memory {
    std::uint64_t pair_list = 0;      // the ordered pairs and their sort
    std::uint64_t filter = 0;         // per-particle boxes and Bodies
    std::uint64_t work = 0;           // one PairWork per evaluated pair
    std::uint64_t records = 0;        // one ContactRecord per evaluated pair, when kept
    std::uint64_t history_pairs = 0;  // the early pairs' table: pairs
    std::uint64_t history_subs = 0;   // ... and sub-contacts
    std::uint64_t early = 0;          // results of pairs evaluated early
  };
  Memory memory() const;

 private:
  /// One pair's law result, as run() needs it to sum and record it.
  struct Evaluated {
    PairLawResult r;
    Vec3 xa, xb;  // the canonical frame's centroids
    contact::Status status = contact::Status::kOk;
    bool touching = false;  // the kernel's verdict (the law may still apply no force)
    bool accepted = false;  // the filter let the pair through (else nothing above is set)
  };
  /// A pair evaluated by runEarly(), waiting for run().
  struct EarlyPair {
    particles::PairKey key;
    Evaluated e;
  };
  /// Filter, kernel, model and law of pair `c` (not `accepted` if the filter rejects it): last
  /// step's history found by `old` (a ContactHistory::Cursor, or the history being rebuilt),
  /// the pair's new history appended to `next`. Returned by value: built in the caller's
  /// variable, where an output argument cost a copy of the law's result per pair.
  template <typename OldHistory>
  Evaluated evaluate(const ContactSetup& setup, const particles::ParticleStorage& storage,
                     const OrderedPair& c, OldHistory& old, particles::ContactHistory& next);
  /// Appends the work entry of the evaluated pair `c` (local_a, local_b: its local free copies).
  void recordWork(const OrderedPair& c, std::int32_t local_a, std::int32_t local_b,
                  const Evaluated& e, bool a_is_local);
  /// Appends its full record.
  void record(const particles::ParticleStorage& storage, const OrderedPair& c, std::int32_t local_a,
              std::int32_t local_b, const Evaluated& e, bool a_is_local);
  /// Appends the early pair's history (pair and sub-contacts) from early_history_ to `history`,
  /// which is being rebuilt.
  void takeEarlyHistory(const particles::PairKey& key, particles::ContactHistory::Cursor& early,
                        particles::ContactHistory& history);

  PairOrder order_;
  PairFilter filter_;
  ContactModelStep model_;
  PairLaw law_;
  std::vector<PairWork> work_;
  std::vector<ContactRecord> records_;
  bool keep_records_ = true;
  [[noreturn]] static void refuseRecords();
  std::vector<EarlyPair> early_;  // in key order
  particles::ContactHistory early_history_;
  ContactSetup early_setup_;
  std::vector<particles::SubEntry> sub_scratch_;
};

}  // namespace polydem::sim
