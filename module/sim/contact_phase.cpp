#include "polydem/sim/contact_phase.h"

#include <algorithm>

#include "polydem/core/error.h"
#include "polydem/core/memory.h"
#include "polydem/dynamics/driver.h"
#include "polydem/sim/force_sum.h"

namespace polydem::sim {

namespace {

// The history of a pair that had none at the last step.
const particles::PairHistory kNoHistory{};

// The centroids and velocities of a pair with a driven body, in the pair's frame: a driven body's
// prescribed velocity field at t - dt/2.
dynamics::PairKinematics drivenKinematics(const ContactSetup& setup,
                                          const particles::ParticleStorage& storage,
                                          const OrderedPair& c, const PairFrame& frame) {
  const double t_half = setup.time - 0.5 * setup.dt;
  auto velocities = [&](std::size_t i, const Vec3& position, Vec3& linear, Vec3& angular) {
    const auto& p = storage[i];
    if (p.isDriven()) {
      const auto state = dynamics::driverState((*setup.drivers)[p.driver], t_half);
      linear = dynamics::materialPointVelocity(state, position);
      angular = state.angular_velocity;
    } else {
      linear = p.velocity;
      angular = storage.angularVelocity(i);
    }
  };
  dynamics::PairKinematics kin;
  kin.xa = frame.xa;
  kin.xb = frame.xb;
  velocities(c.a, frame.xa, kin.va, kin.wa);
  velocities(c.b, frame.xb, kin.vb, kin.wb);
  return kin;
}

}  // namespace

// Inlined into both callers: run() calls it for every candidate pair, and one call per pair
// measured about 1 % more instructions in the 1-rank step (callgrind, 2,000 dense cubes).
template <typename OldHistory>
[[gnu::always_inline]] inline ContactPhase::Evaluated ContactPhase::evaluate(
    const ContactSetup& setup, const particles::ParticleStorage& storage, const OrderedPair& c,
    OldHistory& old, particles::ContactHistory& next) {
  const auto& shapes = *setup.shapes;
  PairFrame frame;
  if (!filter_.accept(storage, shapes, c, setup.margin, frame)) return {};
  const auto& pa = storage[c.a];
  const auto& pb = storage[c.b];
  // The pair's new entry starts as last step's; the kernel (its warm start) and
  // the law write into it in place.
  const auto last = old.find(c.key);
  particles::PairHistory& h = next.appendSorted(c.key, last.pair ? *last.pair : kNoHistory);
  const contact::Body& body_a = *frame.a;
  const contact::Body& body_b = *frame.b;
  const ModelledContact modelled = model_.evaluate(
      *setup.kernel, setup.model, setup.overlap_centroid, body_a, body_b, &h.kernel);

  // Built in place from the particles' velocities, without copies on the stack (this runs for
  // every pair); a driven body's take its prescribed field.
  const dynamics::PairKinematics kin =
      pa.isDriven() || pb.isDriven()
          ? drivenKinematics(setup, storage, c, frame)
          : dynamics::PairKinematics{frame.xa, pa.velocity, storage.angularVelocity(c.a),
                                     frame.xb, pb.velocity, storage.angularVelocity(c.b)};
  const double ma = storage.mass(c.a), mb = storage.mass(c.b);
  const double m_eff = pa.isFree() && pb.isFree() ? ma * mb / (ma + mb) : (pa.isFree() ? ma : mb);
  const auto& law = (*setup.law)[pa.material * setup.materials + pb.material];
  PairJoints joints;
  if (setup.plane_joint && !setup.plane_joint->empty()) {
    joints = {shapes[pa.shape].face_plane,
              shapes[pb.shape].face_plane,
              *setup.plane_joint,
              *setup.joint_law,
              setup.materials,
              pa.material,
              pb.material};
  }
  return {law_.apply(modelled, body_a, body_b, kin, m_eff, setup.dt, law, joints, h, last.sub_keys,
                     last.subs, next),
          frame.xa,
          frame.xb,
          modelled.contact.status,
          modelled.contact.touching,
          true};
}

std::int64_t ContactPhase::runEarly(const ContactSetup& setup,
                                    const particles::ParticleStorage& storage,
                                    std::span<const broadphase::CandidatePair> candidates,
                                    const particles::ContactHistory& history) {
  discardEarly();
  early_setup_ = setup;
  const auto pairs = order_.sort(storage, candidates);
  filter_.prepare(storage, *setup.shapes);
  particles::ContactHistory::Cursor old(history);
  for (std::size_t k = 0; k < pairs.size(); ++k) {
    const OrderedPair& c = pairs[k];
    while (k + 1 < pairs.size() && pairs[k + 1].key == c.key) ++k;  // periodic images
    if (storage[c.a].isDriven() || storage[c.b].isDriven()) continue;
    const EarlyPair pair{c.key, evaluate(setup, storage, c, old, early_history_)};
    if (pair.e.accepted) early_.push_back(pair);
  }
  return static_cast<std::int64_t>(early_.size());
}

void ContactPhase::takeEarlyHistory(const particles::PairKey& key,
                                    particles::ContactHistory::Cursor& early,
                                    particles::ContactHistory& history) {
  history.skipOld(key);  // read by runEarly already
  const auto found = early.find(key);
  if (found.pair) history.appendSorted(key, *found.pair);
  sub_scratch_.clear();
  for (std::size_t s = 0; s < found.subs.size(); ++s)
    sub_scratch_.push_back({found.sub_keys[s].feature, found.subs[s]});
  history.appendSubs(key, sub_scratch_);
}

namespace {

// Last step's entries of the history being rebuilt, as ContactPhase::evaluate reads them.
struct Rebuilding {
  particles::ContactHistory& history;
  particles::ContactHistory::Found find(const particles::PairKey& key) {
    return history.takeOld(key);
  }
};

}  // namespace

ContactPhaseStats ContactPhase::run(const ContactSetup& setup,
                                    const particles::ParticleStorage& storage,
                                    std::span<const broadphase::CandidatePair> candidates,
                                    particles::ContactHistory& history,
                                    std::vector<dynamics::ForceAccumulator>& forces) {
  ContactPhaseStats stats;
  stats.candidates = static_cast<std::int64_t>(candidates.size());
  // The early results hold for this setup alone; the time only reaches driven bodies' pairs,
  // which are never evaluated early.
  ContactSetup same_time = early_setup_;
  same_time.time = setup.time;
  if (!(same_time == setup)) discardEarly();
  const auto pairs = order_.sort(storage, candidates);
  work_.clear();
  records_.clear();
  forces.assign(storage.size(), dynamics::ForceAccumulator{});
  history.beginRebuild();
  Rebuilding old{history};
  particles::ContactHistory::Cursor early_history(early_history_);
  std::size_t next_early = 0;
  filter_.prepare(storage, *setup.shapes);

  auto localFree = [&](std::int32_t i) {
    return static_cast<std::size_t>(i) < storage.localCount() && storage[i].isFree();
  };

  for (std::size_t k = 0; k < pairs.size(); ++k) {
    const OrderedPair& c = pairs[k];
    // Periodic images can yield the same pair twice on one rank: evaluate once, and apply the
    // force to whichever copies of A and B are local.
    std::int32_t local_a = localFree(c.a) ? c.a : -1, local_b = localFree(c.b) ? c.b : -1;
    while (k + 1 < pairs.size() && pairs[k + 1].key == c.key) {
      ++k;
      if (local_a < 0 && localFree(pairs[k].a)) local_a = pairs[k].a;
      if (local_b < 0 && localFree(pairs[k].b)) local_b = pairs[k].b;
    }
    // Both lists are in key order: one merge walk. A pair evaluated early is taken as it is, its
    // history appended here, so that the new table is built in this one order.
    while (next_early < early_.size() && early_[next_early].key < c.key) ++next_early;
    const bool early = next_early < early_.size() && early_[next_early].key == c.key;
    if (early) {
      takeEarlyHistory(c.key, early_history, history);
      ++stats.early;
    }
    const Evaluated e = early ? early_[next_early++].e : evaluate(setup, storage, c, old, history);
    if (!e.accepted) continue;

    ++stats.evaluated;
    const PairLawResult& r = e.r;
    sumPairForce(forces, local_a, local_b, r, e.xa, e.xb);

    const bool a_is_local = static_cast<std::size_t>(c.a) < storage.localCount();
    if (r.touching) {
      ++stats.touching;
      stats.subcontacts += r.subcontacts;
    }
    recordWork(c, local_a, local_b, e, a_is_local);
    if (keep_records_) record(storage, c, local_a, local_b, e, a_is_local);
    countStatus(stats, e.status);
  }
  discardEarly();
  history.endRebuild();
  return stats;
}

void ContactPhase::recordWork(const OrderedPair& c, std::int32_t local_a, std::int32_t local_b,
                              const Evaluated& e, bool a_is_local) {
  // Grown by a quarter, not doubled (core/memory.h reserveFor): kept for the whole run.
  reserveFor(work_, work_.size() + 1);
  PairWork& w = work_.emplace_back();
  w.stored_a = c.a;
  w.stored_b = c.b;
  if (e.r.touching)
    w.subcontacts = static_cast<std::uint16_t>(std::clamp(e.r.subcontacts, 0, 65535));
  w.flags = static_cast<std::uint8_t>(
      (e.touching ? PairWork::kTouching : 0) | (local_a >= 0 ? PairWork::kAFree : 0) |
      (local_b >= 0 ? PairWork::kBFree : 0) | (a_is_local ? PairWork::kALocal : 0));
}

void ContactPhase::record(const particles::ParticleStorage& storage, const OrderedPair& c,
                          std::int32_t local_a, std::int32_t local_b, const Evaluated& e,
                          bool a_is_local) {
  // Written in place: a record built on the stack and pushed cost one more copy of it per pair.
  reserveFor(records_, records_.size() + 1);
  ContactRecord& rec = records_.emplace_back();
  rec.key = c.key;
  rec.a = local_a;
  rec.b = local_b;
  rec.stored_a = c.a;
  rec.stored_b = c.b;
  rec.touching = e.touching;
  rec.status = e.status;
  rec.a_is_local = a_is_local;
  rec.both_free = storage[c.a].isFree() && storage[c.b].isFree();
  const PairLawResult& r = e.r;
  if (!r.touching) return;
  rec.point = r.point;
  rec.normal = r.normal;
  rec.force = r.force;
  rec.normal_force = r.normal_force;
  rec.shear_force = r.shear_force;
  rec.energy = r.energy;
  rec.subcontacts = r.subcontacts;
  rec.joint = r.joint;
}

void ContactPhase::refuseRecords() {
  throw Error(
      "contact records read while the run keeps none (a reader not declared: "
      "Simulation::keepContactRecords, Check::readsContacts)");
}

void ContactPhase::keepRecords(bool keep) {
  keep_records_ = keep;
  if (!keep) records_ = std::vector<ContactRecord>();  // the room too
}

ContactPhase::Memory ContactPhase::memory() const {
  Memory m;
  m.pair_list = order_.heapBytes();
  m.filter = filter_.heapBytes();
  m.work = capacityBytes(work_);
  m.records = capacityBytes(records_);
  m.history_pairs = early_history_.pairBytes();
  m.history_subs = early_history_.subBytes();
  m.early = capacityBytes(early_) + capacityBytes(sub_scratch_);
  return m;
}

}  // namespace polydem::sim
