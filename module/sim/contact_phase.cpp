#include "polydem/sim/contact_phase.h"

#include <algorithm>

#include "polydem/dynamics/driver.h"

namespace polydem::sim {

namespace {

using particles::ParticleStorage;

// A body's pose and velocities in the pair's canonical frame.
struct Placed {
  Vec3 position;
  Vec3 velocity_half;  // of the centroid, at t - dt/2
  Vec3 angular_velocity;
};

// Min/max corner of a vertex set.
void bounds(std::span<const Vec3> v, Vec3& lo, Vec3& hi) {
  lo = hi = v[0];
  for (const Vec3& x : v) {
    lo = lo.cwiseMin(x);
    hi = hi.cwiseMax(x);
  }
}

bool boxesOverlap(const Vec3& alo, const Vec3& ahi, const Vec3& blo, const Vec3& bhi,
                  double slack) {
  return (alo.array() <= bhi.array() + slack).all() && (blo.array() <= ahi.array() + slack).all();
}

bool boxesOverlap(std::span<const Vec3> a, std::span<const Vec3> b, double slack) {
  Vec3 alo, ahi, blo, bhi;
  bounds(a, alo, ahi);
  bounds(b, blo, bhi);
  return boxesOverlap(alo, ahi, blo, bhi, slack);
}

// Candidates of one lower uid ordered by (higher uid, a, b): insertion sort, as the few pairs of
// one particle come nearly ordered from the broad phase.
template <typename Candidate>
void sortBucket(Candidate* first, Candidate* last) {
  auto less = [](const Candidate& x, const Candidate& y) {
    return x.key.hi != y.key.hi ? x.key.hi < y.key.hi : (x.a != y.a ? x.a < y.a : x.b < y.b);
  };
  for (Candidate* i = first + 1; i < last; ++i) {
    const Candidate c = *i;
    Candidate* j = i;
    for (; j > first && less(c, *(j - 1)); --j) *j = *(j - 1);
    *j = c;
  }
}

// World vertices of entry i placed at `position` (used when an image shift moves the frame).
std::span<const Vec3> verticesAt(const ParticleStorage& s, const particles::ShapeTable& shapes,
                                 std::size_t i, const Vec3& position, std::vector<Vec3>& out) {
  const auto& body = shapes[s[i].shape].polyhedron.vertices();
  out.resize(body.size());
  const Mat3& r = s.rotation(i);
  for (std::size_t v = 0; v < body.size(); ++v) out[v] = position + r * body[v];
  return out;
}

}  // namespace

// Key order (lo uid, hi uid, a, b) without comparing pairs: the particles are ranked by uid (one
// sort of the storage, a few times smaller than the pairs), the pairs are bucketed by the rank of
// their lower uid (a counting sort) and each bucket is sorted on its own.
void ContactPhase::sortCandidates(const ParticleStorage& storage,
                                  std::span<const broadphase::CandidatePair> candidates) {
  const std::size_t n = storage.size();
  by_uid_.resize(n);
  for (std::size_t i = 0; i < n; ++i) by_uid_[i] = {storage[i].uid, static_cast<std::int32_t>(i)};
  std::sort(by_uid_.begin(), by_uid_.end());
  uid_rank_.resize(n);
  std::int32_t rank = -1;
  for (std::size_t k = 0; k < n; ++k) {
    if (k == 0 || by_uid_[k].first != by_uid_[k - 1].first) ++rank;  // images share a rank
    uid_rank_[by_uid_[k].second] = rank;
  }
  bucket_start_.assign(static_cast<std::size_t>(rank) + 2, 0);
  for (const auto& c : candidates) {
    const std::int32_t lo = storage[c.i].uid < storage[c.j].uid ? c.i : c.j;
    ++bucket_start_[uid_rank_[lo] + 1];
  }
  for (std::size_t b = 1; b < bucket_start_.size(); ++b) bucket_start_[b] += bucket_start_[b - 1];
  candidates_.resize(candidates.size());
  fill_ = bucket_start_;
  for (const auto& c : candidates) {
    const Uid ui = storage[c.i].uid, uj = storage[c.j].uid;
    const Candidate x = ui < uj ? Candidate{{ui, uj}, c.i, c.j} : Candidate{{uj, ui}, c.j, c.i};
    candidates_[fill_[uid_rank_[x.a]]++] = x;
  }
  for (std::size_t b = 0; b + 1 < bucket_start_.size(); ++b) {
    sortBucket(candidates_.data() + bucket_start_[b], candidates_.data() + bucket_start_[b + 1]);
  }
}

ContactPhaseStats ContactPhase::run(const ContactSetup& setup, const ParticleStorage& storage,
                                    std::span<const broadphase::CandidatePair> candidates,
                                    particles::ContactHistory& history,
                                    std::vector<dynamics::ForceAccumulator>& forces) {
  ContactPhaseStats stats;
  stats.candidates = static_cast<std::int64_t>(candidates.size());
  sortCandidates(storage, candidates);
  records_.clear();
  next_.clear();
  forces.assign(storage.size(), dynamics::ForceAccumulator{});
  const auto& shapes = *setup.shapes;
  particles::ContactHistory::Cursor old(history);
  const double t_half = setup.time - 0.5 * setup.dt;
  // Each particle's box once per step, for the box test of its (unshifted) pairs.
  box_lo_.resize(storage.size());
  box_hi_.resize(storage.size());
  for (std::size_t i = 0; i < storage.size(); ++i) {
    bounds(storage.worldVertices(i), box_lo_[i], box_hi_[i]);
  }

  auto placed = [&](std::size_t i, const Vec3& position) {
    const auto& p = storage[i];
    if (p.isDriven()) {
      const auto state = dynamics::driverState((*setup.drivers)[p.driver], t_half);
      return Placed{position, dynamics::materialPointVelocity(state, position),
                    state.angular_velocity};
    }
    return Placed{position, p.velocity, storage.angularVelocity(i)};
  };
  auto localFree = [&](std::int32_t i) {
    return static_cast<std::size_t>(i) < storage.localCount() && storage[i].isFree();
  };

  for (std::size_t k = 0; k < candidates_.size(); ++k) {
    const Candidate& c = candidates_[k];
    // Periodic images can yield the same pair twice on one rank: evaluate once, and apply the
    // force to whichever copies of A and B are local.
    std::int32_t local_a = localFree(c.a) ? c.a : -1, local_b = localFree(c.b) ? c.b : -1;
    while (k + 1 < candidates_.size() && candidates_[k + 1].key == c.key) {
      ++k;
      if (local_a < 0 && localFree(candidates_[k].a)) local_a = candidates_[k].a;
      if (local_b < 0 && localFree(candidates_[k].b)) local_b = candidates_[k].b;
    }
    const auto& pa = storage[c.a];
    const auto& pb = storage[c.b];
    const auto& sa = shapes[pa.shape];
    const auto& sb = shapes[pb.shape];

    // Canonical frame: A where its owner stores it, B shifted by the difference of the images.
    const Vec3& xa = pa.position;
    const Vec3 xb = pb.position + (storage.shift(c.b) - storage.shift(c.a));
    const double reach = sa.circumradius + sb.circumradius + setup.margin;
    if ((xb - xa).squaredNorm() > reach * reach) continue;
    const bool unshifted = storage.shift(c.a).isZero(0.0) && storage.shift(c.b).isZero(0.0);
    const auto va =
        unshifted ? storage.worldVertices(c.a) : verticesAt(storage, shapes, c.a, xa, scratch_a_);
    const auto vb =
        unshifted ? storage.worldVertices(c.b) : verticesAt(storage, shapes, c.b, xb, scratch_b_);
    const bool boxes = unshifted ? boxesOverlap(box_lo_[c.a], box_hi_[c.a], box_lo_[c.b],
                                                box_hi_[c.b], setup.margin)
                                 : boxesOverlap(va, vb, setup.margin);
    if (!boxes) continue;

    ++stats.evaluated;
    particles::PairHistory h;
    if (const auto* previous = old.seek(c.key)) h = *previous;
    const auto [old_sub_keys, old_subs] = old.subs(c.key);
    contact::Body body_a{&sa.polyhedron, xa, storage.rotation(c.a), va};
    contact::Body body_b{&sb.polyhedron, xb, storage.rotation(c.b), vb};
    contact::Contact contact = setup.sub_contacts
                                   ? setup.kernel->collideForSubContacts(body_a, body_b, &h.kernel)
                                   : setup.kernel->collide(body_a, body_b, &h.kernel);
    const bool split = setup.sub_contacts && contact.model == contact::ForceModel::kPenalty;
    if (setup.overlap_centroid && !split) contact = overlap_.apply(body_a, body_b, contact);

    ContactRecord rec;
    rec.key = c.key;
    rec.a = local_a;
    rec.b = local_b;
    rec.stored_a = c.a;
    rec.stored_b = c.b;
    rec.touching = contact.touching;
    rec.status = contact.status;
    rec.a_is_local = static_cast<std::size_t>(c.a) < storage.localCount();
    rec.both_free = pa.isFree() && pb.isFree();
    const Placed a = placed(c.a, xa), b = placed(c.b, xb);
    const double ma = storage.mass(c.a), mb = storage.mass(c.b);
    const double m_eff = pa.isFree() && pb.isFree() ? ma * mb / (ma + mb) : (pa.isFree() ? ma : mb);
    const auto& law = (*setup.law)[pa.material * setup.materials + pb.material];
    if (split && contact.touching) {
      // Sub-contacts: a spring at every corner of the face overlap, each with its own history.
      const auto fc = face_.build(body_a, body_b, contact);
      const dynamics::PairKinematics kin{xa, a.velocity_half, a.angular_velocity,
                                         xb, b.velocity_half, b.angular_velocity};
      const auto f =
          dynamics::subContactForces(fc, old_sub_keys, old_subs, kin, m_eff, setup.dt, law, kept_);
      h.shear_force.setZero();
      h.normal = contact.normal;
      h.touching = 1;
      next_.appendSorted(c.key, h);
      for (const auto& s : kept_) next_.appendSub({c.key, s.feature}, s.history);
      ++stats.touching;
      stats.subcontacts += f.loaded;
      rec.point = f.centre;
      rec.normal = contact.normal;
      rec.force = f.force;
      rec.normal_force = f.normal;
      rec.shear_force = f.shear;
      rec.subcontacts = f.loaded;
      rec.energy = f.energy;
      if (local_a >= 0) forces[local_a].addPair(f.force, f.torque_a);
      if (local_b >= 0) forces[local_b].addPair(-f.force, f.torque_b);
    } else {
      const Vec3 v_rel =
          contact.touching ? dynamics::relativeVelocity(contact.point, a.position, a.velocity_half,
                                                        a.angular_velocity, b.position,
                                                        b.velocity_half, b.angular_velocity)
                           : Vec3::Zero();
      const auto f = dynamics::contactForce(contact, v_rel, m_eff, setup.dt, law, h);
      next_.appendSorted(c.key, h);
      if (contact.touching) {
        ++stats.touching;
        rec.point = contact.point;
        rec.normal = contact.normal;
        rec.force = f.force;
        rec.normal_force = f.normal;
        rec.shear_force = f.shear;
        if (contact.model == contact::ForceModel::kPenalty) {
          rec.energy = 0.5 * f.normal_elastic * contact.depth;
        }
        if (local_a >= 0) forces[local_a].addContact(f.force, contact.point, xa);
        if (local_b >= 0) forces[local_b].addContact(-f.force, contact.point, xb);
      }
    }
    stats.not_converged += contact.status == contact::Status::kNotConverged;
    stats.degenerate += contact.status == contact::Status::kDegenerate;
    stats.inner_domain += contact.status == contact::Status::kInnerDomainReached;
    records_.push_back(rec);
  }
  std::swap(history, next_);
  return stats;
}

}  // namespace polydem::sim
