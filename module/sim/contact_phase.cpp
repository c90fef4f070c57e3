#include "polydem/sim/contact_phase.h"

#include "polydem/dynamics/driver.h"
#include "polydem/sim/force_sum.h"

namespace polydem::sim {

ContactPhaseStats ContactPhase::run(const ContactSetup& setup,
                                    const particles::ParticleStorage& storage,
                                    std::span<const broadphase::CandidatePair> candidates,
                                    particles::ContactHistory& history,
                                    std::vector<dynamics::ForceAccumulator>& forces) {
  ContactPhaseStats stats;
  stats.candidates = static_cast<std::int64_t>(candidates.size());
  const auto pairs = order_.sort(storage, candidates);
  records_.clear();
  next_.clear();
  forces.assign(storage.size(), dynamics::ForceAccumulator{});
  const auto& shapes = *setup.shapes;
  particles::ContactHistory::Cursor old(history);
  const double t_half = setup.time - 0.5 * setup.dt;
  filter_.prepare(storage);

  // A body's motion in the pair's frame: a driven body's prescribed velocity field at t - dt/2.
  auto motion = [&](std::size_t i, const Vec3& position) {
    const auto& p = storage[i];
    if (p.isDriven()) {
      const auto state = dynamics::driverState((*setup.drivers)[p.driver], t_half);
      return PairMotion{position, dynamics::materialPointVelocity(state, position),
                        state.angular_velocity};
    }
    return PairMotion{position, p.velocity, storage.angularVelocity(i)};
  };
  auto localFree = [&](std::int32_t i) {
    return static_cast<std::size_t>(i) < storage.localCount() && storage[i].isFree();
  };

  PairFrame frame;
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
    if (!filter_.accept(storage, shapes, c, setup.margin, frame)) continue;

    ++stats.evaluated;
    const auto& pa = storage[c.a];
    const auto& pb = storage[c.b];
    particles::PairHistory h;
    if (const auto* previous = old.seek(c.key)) h = *previous;
    const auto [old_sub_keys, old_subs] = old.subs(c.key);
    const contact::Body body_a{&shapes[pa.shape].polyhedron, frame.xa, storage.rotation(c.a),
                               frame.va, storage.worldFaceNormals(c.a)};
    const contact::Body body_b{&shapes[pb.shape].polyhedron, frame.xb, storage.rotation(c.b),
                               frame.vb, storage.worldFaceNormals(c.b)};
    const ModelledContact modelled = model_.evaluate(
        *setup.kernel, setup.model, setup.overlap_centroid, body_a, body_b, &h.kernel);

    const PairMotion a = motion(c.a, frame.xa), b = motion(c.b, frame.xb);
    const double ma = storage.mass(c.a), mb = storage.mass(c.b);
    const double m_eff = pa.isFree() && pb.isFree() ? ma * mb / (ma + mb) : (pa.isFree() ? ma : mb);
    const auto& law = (*setup.law)[pa.material * setup.materials + pb.material];
    const PairLawResult r = law_.apply(c.key, modelled, body_a, body_b, a, b, m_eff, setup.dt, law,
                                       h, old_sub_keys, old_subs, next_);
    sumPairForce(forces, local_a, local_b, r, frame.xa, frame.xb);

    ContactRecord rec;
    rec.key = c.key;
    rec.a = local_a;
    rec.b = local_b;
    rec.stored_a = c.a;
    rec.stored_b = c.b;
    rec.touching = modelled.contact.touching;
    rec.status = modelled.contact.status;
    rec.a_is_local = static_cast<std::size_t>(c.a) < storage.localCount();
    rec.both_free = pa.isFree() && pb.isFree();
    if (r.touching) {
      ++stats.touching;
      stats.subcontacts += r.subcontacts;
      rec.point = r.point;
      rec.normal = r.normal;
      rec.force = r.force;
      rec.normal_force = r.normal_force;
      rec.shear_force = r.shear_force;
      rec.energy = r.energy;
      rec.subcontacts = r.subcontacts;
    }
    countStatus(stats, modelled.contact.status);
    records_.push_back(rec);
  }
  std::swap(history, next_);
  return stats;
}

}  // namespace polydem::sim
