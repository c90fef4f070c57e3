#include "polydem/dynamics/sub_contact_law.h"

#include <algorithm>
#include <cmath>

namespace polydem::dynamics {

namespace {

// The pair's normal and shear stiffness: per pair (N/m), or per area times the area of a face
// contact when the interaction gives a joint stiffness (Pa/m).
double pairStiffness(double per_pair, double per_area, const contact::FaceContact& fc) {
  return per_area > 0.0 && fc.kind == contact::ContactArea::kFace ? per_area * fc.area : per_pair;
}

// The shear the vanished sub-contacts stored (their springs' forces, summed), and the total weight
// of the sub-contacts in compression that had no history, both summed in key order.
struct Handover {
  Vec3 shear = Vec3::Zero();
  double newcomer_weight = 0.0;
};

template <typename T>
void grow(std::vector<T>& buffer, std::size_t size) {
  if (buffer.size() < size) buffer.resize(size);
}

Vec3 at(const VecLanes& v, std::size_t i) {
  return {v.x[i], v.y[i], v.z[i]};
}

void put(const VecLanes& v, std::size_t i, const Vec3& value) {
  v.x[i] = value.x();
  v.y[i] = value.y();
  v.z[i] = value.z();
}

// Lane `to` made a copy of lane `from` (every input of the passes).
void copyLane(const SubLanes& l, std::size_t from, std::size_t to) {
  for (const VecLanes* v : {&l.point, &l.normal, &l.shear, &l.old_normal}) {
    put(*v, to, at(*v, from));
  }
  l.gap[to] = l.gap[from];
  l.weight[to] = l.weight[from];
}

// The history pass, one merge walk over the new and the old sub-contacts: every sub-contact in
// compression becomes a lane, with the shear and normal of its own spring of the last step if it
// has one; the lanes without are listed in `uncarried`, with a zero shear and their new normal as
// the old one (so that turning it is harmless); the vanished sub-contacts' shears are summed.
// Returns the number of lanes.
std::size_t gatherLanes(const contact::FaceContact& fc, std::span<const particles::SubKey> old_keys,
                        std::span<const particles::SubHistory> old, const SubLanes& l,
                        std::uint32_t* index, SubContactScratch::Uncarried* uncarried,
                        std::size_t& uncarried_count, Handover& given) {
  std::size_t lanes = 0, j = 0;
  uncarried_count = 0;
  for (std::size_t i = 0; i < fc.subs.size(); ++i) {
    const auto& s = fc.subs[i];
    while (j < old_keys.size() && old_keys[j].feature < s.feature)
      given.shear += old[j++].shear_force;
    const particles::SubHistory* previous = nullptr;
    if (j < old_keys.size() && old_keys[j].feature == s.feature) previous = &old[j++];
    if (!(s.gap > 0.0)) continue;  // apart: no force, its spring is released

    put(l.point, lanes, s.point);
    put(l.normal, lanes, s.normal);
    l.gap[lanes] = s.gap;
    l.weight[lanes] = s.weight;
    index[lanes] = static_cast<std::uint32_t>(i);
    if (previous && previous->normal.squaredNorm() > 0.0) {
      put(l.shear, lanes, previous->shear_force);
      put(l.old_normal, lanes, previous->normal);
    } else {
      // A newcomer (no history) takes its share of the handover; a history without a normal
      // has no shear yet.
      if (!previous) given.newcomer_weight += s.weight;
      put(l.shear, lanes, Vec3::Zero());
      put(l.old_normal, lanes, s.normal);
      uncarried[uncarried_count++] = {static_cast<std::uint32_t>(lanes), !previous};
    }
    ++lanes;
  }
  for (; j < old_keys.size(); ++j) given.shear += old[j].shear_force;
  return lanes;
}

// The shear the uncarried lanes start from: zero, or a newcomer's share of the handover, by
// weight, projected onto its plane.
void startUncarried(const contact::FaceContact& fc, const SubLanes& l, const std::uint32_t* index,
                    std::span<const SubContactScratch::Uncarried> uncarried,
                    const Handover& given) {
  for (const auto& u : uncarried) {
    Vec3 shear = Vec3::Zero();
    if (u.newcomer && given.newcomer_weight > 0.0) {
      const auto& s = fc.subs[index[u.lane]];
      shear = (s.weight / given.newcomer_weight) * given.shear;
      shear -= shear.dot(s.normal) * s.normal;
    }
    put(l.shear, u.lane, shear);
  }
}

// The sums over the lanes, in key order, and the kept histories.
PairForce sumInKeyOrder(const contact::FaceContact& fc, const SubLanes& l, std::size_t lanes,
                        const std::uint32_t* index, bool shear_energy,
                        const particles::SubSlots& kept) {
  Vec3 force = Vec3::Zero(), torque_a = Vec3::Zero(), torque_b = Vec3::Zero();
  Vec3 centre_sum = Vec3::Zero(), shear_sum = Vec3::Zero();
  double normal_sum = 0.0, energy = 0.0, sliding = 0.0;
  for (std::size_t i = 0; i < lanes; ++i) {
    const Vec3 shear = at(l.shear, i);
    force += at(l.force, i);
    torque_a += at(l.torque_a, i);
    torque_b -= at(l.torque_b, i);
    normal_sum += l.normal_force[i];
    energy += l.elastic_energy[i];
    if (shear_energy) energy += l.shear_energy[i];
    centre_sum += at(l.centre, i);
    shear_sum += shear;
    sliding = std::max(sliding, l.sliding[i]);
    kept.keys[i].feature = fc.subs[index[i]].feature;
    kept.entries[i] = {shear, at(l.normal, i)};
  }
  PairForce out;
  out.force = force;
  out.torque_a = torque_a;
  out.torque_b = torque_b;
  out.normal = normal_sum;
  out.energy = energy;
  out.loaded = static_cast<int>(lanes);
  out.sliding = sliding > 0.0;
  out.shear = shear_sum.norm();
  if (normal_sum > 0.0) {
    out.centre = centre_sum / normal_sum;
  } else {
    Vec3 point_sum = Vec3::Zero();
    for (const auto& s : fc.subs) point_sum += s.point;
    out.centre = point_sum / static_cast<double>(fc.subs.size());
  }
  return out;
}

}  // namespace

PairForce subContactForces(const contact::FaceContact& fc,
                           std::span<const particles::SubKey> old_keys,
                           std::span<const particles::SubHistory> old, const PairKinematics& kin,
                           double m_eff, double dt, const LawCoefficients& k,
                           std::vector<SubState>& kept) {
  SubContactScratch scratch;
  std::vector<particles::SubKey> keys(fc.subs.size());
  std::vector<particles::SubHistory> entries(fc.subs.size());
  const PairForce out =
      subContactForces(fc, old_keys, old, kin, m_eff, dt, k, {keys, entries}, scratch);
  kept.clear();
  for (int i = 0; i < out.loaded; ++i) kept.push_back({keys[i].feature, entries[i]});
  return out;
}

PairForce subContactForces(const contact::FaceContact& fc,
                           std::span<const particles::SubKey> old_keys,
                           std::span<const particles::SubHistory> old, const PairKinematics& kin,
                           double m_eff, double dt, const LawCoefficients& k,
                           const particles::SubSlots& kept, SubContactScratch& scratch) {
  PairConstants c{kin.xa, kin.va, kin.wa, kin.xb, kin.vb, kin.wb};
  c.kn = pairStiffness(k.kn, k.jkn, fc);
  c.ks = pairStiffness(k.ks, k.jks, fc);
  // The pair's dashpot, 2 zeta sqrt(m_eff Kn), shared by weight: a uniform approach meets the
  // same damping as a single-point contact would.
  c.dashpot =
      k.damping_ratio > 0.0 && c.kn > 0.0 ? 2.0 * k.damping_ratio * std::sqrt(m_eff * c.kn) : 0.0;
  c.dt = dt;
  c.tan_friction = k.tan_friction;
  c.cohesion = k.cohesion;
  const std::size_t m = fc.subs.size();
  const SubLanes l = scratch.lanes.open(m);
  grow(scratch.index, m);
  grow(scratch.uncarried, m);

  // The history pass; then, apart from the few lanes without a carried shear, every pass runs
  // over all lanes, two at a time: an odd count gets a copy of its last lane, whose results are
  // not read.
  Handover given;
  std::size_t uncarried = 0;
  const std::size_t lanes = gatherLanes(fc, old_keys, old, l, scratch.index.data(),
                                        scratch.uncarried.data(), uncarried, given);
  const std::size_t even = (lanes + 1) & ~std::size_t{1};
  if (even > lanes) copyLane(l, lanes - 1, lanes);
  turnCarriedShears(l, even, 0.5 * (kin.wa + kin.wb), 0.5 * dt);
  startUncarried(fc, l, scratch.index.data(), {scratch.uncarried.data(), uncarried}, given);
  springForces(l, even, c);
  return sumInKeyOrder(fc, l, lanes, scratch.index.data(), c.ks > 0.0, kept);
}

}  // namespace polydem::dynamics
