#include "polydem/dynamics/sub_contact_law.h"

#include <algorithm>
#include <cmath>

#include "polydem/dynamics/joint_laws.h"

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

// Where the shear a sub-contact brings into the step comes from.
enum Origin : std::uint8_t {
  kOpen,      // apart (gap <= 0): no force, its spring is released
  kFresh,     // a history without a normal: no shear yet
  kCarried,   // its own spring of the last step, turned onto the new plane
  kNewcomer,  // no history: its share of the vanished sub-contacts' shear
};

template <typename T>
void grow(std::vector<T>& buffer, std::size_t size) {
  if (buffer.size() < size) buffer.resize(size);
}

}  // namespace

PairForce subContactForces(const contact::FaceContact& fc,
                           std::span<const particles::SubFeature> old_keys,
                           std::span<const particles::SubHistory> old, const PairKinematics& kin,
                           double m_eff, double dt, const LawCoefficients& k,
                           std::vector<particles::SubEntry>& kept) {
  SubContactScratch scratch;
  std::vector<particles::SubFeature> keys(fc.subs.size());
  std::vector<particles::SubHistory> entries(fc.subs.size());
  const PairForce out =
      subContactForces(fc, old_keys, old, kin, m_eff, dt, k, {keys, entries}, scratch);
  kept.clear();
  for (int i = 0; i < out.kept; ++i) kept.push_back({keys[i].feature, entries[i]});
  return out;
}

namespace {

// The law's constants of one pair, the same for all its sub-contacts.
template <typename Law>
struct PairConstants {
  double kn = 0.0, ks = 0.0;  // the pair's stiffnesses, N/m
  double dashpot = 0.0;       // 2 zeta sqrt(m_eff Kn), shared by weight
  double cohesion = 0.0;      // N, the pair's whole cohesion
  double tension = 0.0;       // N, the pair's whole tensile strength
  double open_gap = 0.0;      // the gap below which a sub-contact is open
  double half_dt = 0.0;
  Vec3 spin = Vec3::Zero();  // the pair's mean spin, which turns a carried shear
  typename Law::Pair law_pair;
};

template <typename Law>
PairConstants<Law> pairConstants(const contact::FaceContact& fc, const PairKinematics& kin,
                                 double m_eff, double dt, const LawCoefficients& k) {
  PairConstants<Law> c;
  c.kn = pairStiffness(k.kn, k.jkn, fc);
  c.ks = pairStiffness(k.ks, k.jks, fc);
  // The pair's dashpot, 2 zeta sqrt(m_eff Kn), shared by weight: a uniform approach meets the
  // same damping as a single-point contact would.
  c.dashpot =
      k.damping_ratio > 0.0 && c.kn > 0.0 ? 2.0 * k.damping_ratio * std::sqrt(m_eff * c.kn) : 0.0;
  // A joint's strengths are stresses over the face contact's area (0 for a material pair, whose
  // cohesion is a force per pair): w_i A c adds to sub-contact i's shear cap, and its normal
  // spring may pull up to w_i A sigma_t, which it does as long as its gap is above
  // -A sigma_t / Kn (Kn = jkn A: -sigma_t / jkn). For a material pair the sum below is exact
  // (k.cohesion + 0) and the open gap is 0: the same bits as a law without joints.
  const double area = fc.kind == contact::ContactArea::kFace ? fc.area : 0.0;
  c.cohesion = k.cohesion + area * k.cohesion_stress;
  c.tension = area * k.tensile_strength;
  c.open_gap = c.tension > 0.0 && c.kn > 0.0 ? -c.tension / c.kn : 0.0;
  c.law_pair = Law::prepare(k, area);
  c.spin = 0.5 * (kin.wa + kin.wb);
  // Hoisted (0.5 * dt * x is (0.5 * dt) * x): recomputed per sub-contact in the loop otherwise.
  c.half_dt = 0.5 * dt;
  return c;
}

// Pass 1, one merge walk over the new and the old sub-contacts: each one's history and origin,
// the shear it carries over (two divisions each, independent from one sub-contact to the next, so
// that they overlap instead of waiting for each other) and the handover. Fills scratch.origin,
// scratch.carried and, for a law with history, scratch.state and scratch.had_history.
template <typename Law>
Handover carryOver(const contact::FaceContact& fc, std::span<const particles::SubFeature> old_keys,
                   std::span<const particles::SubHistory> old, const PairConstants<Law>& c,
                   SubContactScratch& scratch) {
  constexpr bool kHistory = Law::kHistoryColumns.size() > 0;
  using State = std::array<double, particles::kMaxLawHistory>;
  const std::size_t m = fc.subs.size();
  grow(scratch.carried, m);
  grow(scratch.origin, m);
  Vec3* carried = scratch.carried.data();
  std::uint8_t* origin = scratch.origin.data();
  [[maybe_unused]] State* state = nullptr;
  // What a sub-contact that appears in the pair inherits (the law's rule).
  [[maybe_unused]] State inherited{};
  if constexpr (kHistory) {
    grow(scratch.state, m);
    grow(scratch.had_history, m);
    state = scratch.state.data();
    Law::inherit(old_keys, old, fc, inherited.data());
  }
  Handover given;
  std::size_t j = 0;
  for (std::size_t i = 0; i < m; ++i) {
    const auto& s = fc.subs[i];
    while (j < old_keys.size() && old_keys[j].feature < s.feature)
      given.shear += old[j++].shear_force;
    const particles::SubHistory* previous = nullptr;
    if (j < old_keys.size() && old_keys[j].feature == s.feature) previous = &old[j++];
    double gap = s.gap, opens_at = c.open_gap;
    if constexpr (kHistory) {
      state[i] = previous ? previous->law : inherited;
      scratch.had_history[i] = previous != nullptr;
      gap = Law::effectiveGap(s.gap, state[i].data());
      opens_at = Law::openGap(state[i].data(), c.open_gap);
    }
    if (!(gap > opens_at)) {
      origin[i] = kOpen;
    } else if (previous && previous->normal.squaredNorm() > 0.0) {
      const Vec3 rotated = rotateShear(previous->shear_force, previous->normal, s.normal);
      carried[i] = spinShear(rotated, s.normal, c.half_dt * c.spin.dot(s.normal));
      origin[i] = kCarried;
    } else if (!previous) {
      given.newcomer_weight += s.weight;
      origin[i] = kNewcomer;
    } else {
      origin[i] = kFresh;
    }
  }
  for (; j < old_keys.size(); ++j) given.shear += old[j].shear_force;
  return given;
}

// The force of one sub-contact in compression (or held in tension by the joint).
struct SubForce {
  double f_normal = 0.0, f_elastic = 0.0, gap = 0.0;
  Vec3 shear = Vec3::Zero();
  bool slipped = false;
};

// Sub-contact i's spring forces: the normal spring and dashpot, the shear spring grown from what
// it carries (its origin) by the tangential motion, capped by the law (which updates `h`, the
// sub-contact's history, when it slips).
template <typename Law>
SubForce subForce(const contact::SubContact& s, std::uint8_t origin, const Vec3& carried,
                  const Handover& given, const Vec3& v, double dt, const PairConstants<Law>& c,
                  const LawCoefficients& k, [[maybe_unused]] double* h) {
  constexpr bool kHistory = Law::kHistoryColumns.size() > 0;
  SubForce out;
  const Vec3& n = s.normal;
  const double w = s.weight;
  double gap = s.gap, pull = c.tension;
  if constexpr (kHistory) {
    gap = Law::effectiveGap(s.gap, h);
    pull = Law::tension(h, c.tension);
  }
  const double v_normal = v.dot(n);
  const double f_elastic = w * c.kn * gap;
  out.f_normal = std::max(f_elastic - w * c.dashpot * v_normal, pull > 0.0 ? -w * pull : 0.0);
  Vec3 shear = Vec3::Zero();
  if (origin == kCarried) {
    shear = carried;
  } else if (origin == kNewcomer && given.newcomer_weight > 0.0) {
    shear = (w / given.newcomer_weight) * given.shear;
    shear -= shear.dot(n) * n;
  }
  const Vec3 v_tangent = v - v_normal * n;
  shear -= (w * c.ks * dt) * v_tangent;
  double slide = 0.0;
  if constexpr (kHistory) slide = v_tangent.norm() * dt;
  const double cap = Law::cap(c.law_pair, k, f_elastic, w, c.cohesion, gap, slide, h);
  const double magnitude = shear.norm();
  if (magnitude > cap) {
    shear *= cap / magnitude;
    out.slipped = true;
    if constexpr (kHistory) Law::slipped(c.law_pair, k, gap, slide, h);
  }
  out.f_elastic = f_elastic;
  out.gap = gap;
  out.shear = shear;
  return out;
}

// An opened sub-contact keeps its history when the law says so (coulomb-residual: it stays
// broken), as slot `stored` of `kept`, with no spring force. Returns the slots it took (0 or 1).
template <typename Law>
std::size_t keepOpen(const contact::SubContact& s, SubContactScratch& scratch, std::size_t i,
                     const particles::SubSlots& kept, std::size_t stored) {
  if (!Law::keepOpen(scratch.had_history[i] != 0, scratch.state[i].data())) return 0;
  kept.keys[stored].feature = s.feature;
  kept.entries[stored].shear_force.setZero();
  kept.entries[stored].normal.setZero();
  kept.entries[stored].law = scratch.state[i];
  return 1;
}

// The law of one pair, for the joint law `Law` (dynamics/joint_law_coulomb.h lists its hooks).
// Laws without history (coulomb, material pairs) skip every history step at compile time, so their
// arithmetic is the plain Coulomb law's.
template <typename Law>
PairForce pairForces(const contact::FaceContact& fc,
                     std::span<const particles::SubFeature> old_keys,
                     std::span<const particles::SubHistory> old, const PairKinematics& kin,
                     double m_eff, double dt, const LawCoefficients& k,
                     const particles::SubSlots& kept, SubContactScratch& scratch) {
  constexpr bool kHistory = Law::kHistoryColumns.size() > 0;
  const PairConstants<Law> c = pairConstants<Law>(fc, kin, m_eff, dt, k);
  const Handover given = carryOver<Law>(fc, old_keys, old, c, scratch);
  const std::size_t m = fc.subs.size();
  const Vec3* carried = scratch.carried.data();
  const std::uint8_t* origin = scratch.origin.data();

  // Pass 2, in key order: the springs' forces and their sums. The sums live in locals until the
  // end: the kept histories are written through pointers, which the compiler must otherwise
  // assume may alias `out`. The sum of the points, needed only when no sub-contact is in
  // compression, is taken after the loop (the same sum in the same order), which keeps three
  // registers free in it.
  Vec3 force = Vec3::Zero(), torque_a = Vec3::Zero(), torque_b = Vec3::Zero();
  Vec3 centre_sum = Vec3::Zero(), shear_sum = Vec3::Zero();
  double normal_sum = 0.0, energy = 0.0;
  std::size_t loaded = 0, stored = 0;
  bool sliding = false;
  const Vec3 xa = kin.xa, va = kin.va, wa = kin.wa, xb = kin.xb, vb = kin.vb, wb = kin.wb;
  for (std::size_t i = 0; i < m; ++i) {
    const auto& s = fc.subs[i];
    double* h = nullptr;
    if constexpr (kHistory) h = scratch.state[i].data();
    if (origin[i] == kOpen) {
      if constexpr (kHistory) stored += keepOpen<Law>(s, scratch, i, kept, stored);
      continue;
    }
    const Vec3 v = relativeVelocity(s.point, xa, va, wa, xb, vb, wb);
    const SubForce sf = subForce<Law>(s, origin[i], carried[i], given, v, dt, c, k, h);
    sliding = sliding || sf.slipped;
    const Vec3 f = sf.f_normal * s.normal + sf.shear;
    force += f;
    torque_a += (s.point - xa).cross(f);
    torque_b -= (s.point - xb).cross(f);
    normal_sum += sf.f_normal;
    energy += 0.5 * sf.f_elastic * sf.gap;
    if (c.ks > 0.0) energy += 0.5 * sf.shear.squaredNorm() / (s.weight * c.ks);
    centre_sum += sf.f_normal * s.point;
    shear_sum += sf.shear;
    // Field by field: an aggregate assigned whole was built on the stack first.
    kept.keys[stored].feature = s.feature;
    kept.entries[stored].shear_force = sf.shear;
    kept.entries[stored].normal = s.normal;
    if constexpr (kHistory) {
      kept.entries[stored].law = scratch.state[i];
    } else {
      kept.entries[stored].law = {};
    }
    ++stored;
    ++loaded;
  }
  PairForce out;
  out.force = force;
  out.torque_a = torque_a;
  out.torque_b = torque_b;
  out.normal = normal_sum;
  out.energy = energy;
  out.loaded = static_cast<int>(loaded);
  out.kept = static_cast<int>(stored);
  out.sliding = sliding;
  out.shear = shear_sum.norm();
  if (out.normal > 0.0) {
    out.centre = centre_sum / out.normal;
  } else {
    Vec3 point_sum = Vec3::Zero();
    for (const auto& s : fc.subs) point_sum += s.point;
    out.centre = point_sum / static_cast<double>(fc.subs.size());
  }
  return out;
}

}  // namespace

PairForce subContactForces(const contact::FaceContact& fc,
                           std::span<const particles::SubFeature> old_keys,
                           std::span<const particles::SubHistory> old, const PairKinematics& kin,
                           double m_eff, double dt, const LawCoefficients& k,
                           const particles::SubSlots& kept, SubContactScratch& scratch) {
  // Static dispatch, once per pair: each law's loop is its own instantiation.
  switch (k.law) {
#define POLYDEM_JOINT_LAW(id, type) \
  case JointLaw::id:                \
    return pairForces<type>(fc, old_keys, old, kin, m_eff, dt, k, kept, scratch);
#include "polydem/dynamics/joint_law_list.inc"
#undef POLYDEM_JOINT_LAW
  }
  return {};
}

}  // namespace polydem::dynamics
