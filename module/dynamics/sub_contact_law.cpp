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
// of the sub-contacts in compression that had no history: one merge walk over the two sorted lists.
struct Handover {
  Vec3 shear = Vec3::Zero();
  double newcomer_weight = 0.0;
};

Handover handover(std::span<const contact::SubContact> subs,
                  std::span<const particles::SubKey> old_keys,
                  std::span<const particles::SubHistory> old) {
  Handover h;
  std::size_t j = 0;
  for (const auto& s : subs) {
    while (j < old_keys.size() && old_keys[j].feature < s.feature) h.shear += old[j++].shear_force;
    if (j < old_keys.size() && old_keys[j].feature == s.feature) {
      ++j;
    } else if (s.gap > 0.0) {
      h.newcomer_weight += s.weight;
    }
  }
  for (; j < old_keys.size(); ++j) h.shear += old[j].shear_force;
  return h;
}

}  // namespace

Vec3 spinShear(const Vec3& shear, const Vec3& n, double t) {
  const double tt = t * t;
  return ((1.0 - tt) * shear + (2.0 * t) * n.cross(shear)) / (1.0 + tt);
}

PairForce subContactForces(const contact::FaceContact& fc,
                           std::span<const particles::SubKey> old_keys,
                           std::span<const particles::SubHistory> old, const PairKinematics& kin,
                           double m_eff, double dt, const LawCoefficients& k,
                           std::vector<SubState>& kept) {
  PairForce out;
  kept.clear();
  const double kn = pairStiffness(k.kn, k.jkn, fc);
  const double ks = pairStiffness(k.ks, k.jks, fc);
  // The pair's dashpot, 2 zeta sqrt(m_eff Kn), shared by weight: a uniform approach meets the
  // same damping as a single-point contact would.
  const double dashpot =
      k.damping_ratio > 0.0 && kn > 0.0 ? 2.0 * k.damping_ratio * std::sqrt(m_eff * kn) : 0.0;
  const Vec3 spin = 0.5 * (kin.wa + kin.wb);
  const Handover given = handover(fc.subs, old_keys, old);

  Vec3 centre_sum = Vec3::Zero(), shear_sum = Vec3::Zero(), point_sum = Vec3::Zero();
  std::size_t j = 0;
  for (const auto& s : fc.subs) {
    point_sum += s.point;
    while (j < old_keys.size() && old_keys[j].feature < s.feature) ++j;
    const particles::SubHistory* previous =
        j < old_keys.size() && old_keys[j].feature == s.feature ? &old[j] : nullptr;
    if (!(s.gap > 0.0)) continue;  // an open corner: no force, its spring is released

    const Vec3& n = s.normal;
    const double w = s.weight;
    const Vec3 v = relativeVelocity(s.point, kin.xa, kin.va, kin.wa, kin.xb, kin.vb, kin.wb);
    const double v_normal = v.dot(n);
    const double f_elastic = w * kn * s.gap;
    const double f_normal = std::max(f_elastic - w * dashpot * v_normal, 0.0);

    Vec3 shear = Vec3::Zero();
    if (previous && previous->normal.squaredNorm() > 0.0) {
      shear = rotateShear(previous->shear_force, previous->normal, n);
      shear = spinShear(shear, n, 0.5 * dt * spin.dot(n));
    } else if (!previous && given.newcomer_weight > 0.0) {
      shear = (w / given.newcomer_weight) * given.shear;
      shear -= shear.dot(n) * n;
    }
    shear -= (w * ks * dt) * (v - v_normal * n);
    const double cap = f_elastic * k.tan_friction + w * k.cohesion;
    const double magnitude = shear.norm();
    if (magnitude > cap) {
      shear *= cap / magnitude;
      out.sliding = true;
    }

    const Vec3 f = f_normal * n + shear;
    out.force += f;
    out.torque_a += (s.point - kin.xa).cross(f);
    out.torque_b -= (s.point - kin.xb).cross(f);
    out.normal += f_normal;
    out.energy += 0.5 * f_elastic * s.gap;
    if (ks > 0.0) out.energy += 0.5 * shear.squaredNorm() / (w * ks);
    centre_sum += f_normal * s.point;
    shear_sum += shear;
    ++out.loaded;
    kept.push_back({s.feature, {shear, n}});
  }
  out.shear = shear_sum.norm();
  out.centre = out.normal > 0.0 ? Vec3(centre_sum / out.normal)
                                : Vec3(point_sum / static_cast<double>(fc.subs.size()));
  return out;
}

}  // namespace polydem::dynamics
