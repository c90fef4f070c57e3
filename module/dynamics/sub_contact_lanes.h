// The element-wise part of the sub-contact law (sub_contact_law.h), as passes over a pair's
// sub-contacts in compression stored as structure of arrays: one array ("lane array") per
// coordinate, one entry ("lane") per sub-contact. Each pass does the same operations in the same
// order for every lane, with no sums across lanes, so the compiler runs two lanes per SSE2
// instruction (packed add, multiply, divide and square root round every lane exactly as their
// scalar forms do: the same bits as one sub-contact at a time). What is summed over the
// sub-contacts, in key order, is left to the caller.
#pragma once

#include <cstddef>
#include <vector>

#include "polydem/core/types.h"

namespace polydem::dynamics {

/// The x, y and z lane arrays of one vector per sub-contact.
struct VecLanes {
  double* x = nullptr;
  double* y = nullptr;
  double* z = nullptr;
};

/// The lane arrays of one pair, views into SubContactLanes::storage.
struct SubLanes {
  // Gathered from the sub-contacts and last step's history:
  VecLanes point, normal;  // p_i, n_i
  double* gap = nullptr;
  double* weight = nullptr;
  VecLanes shear;       // in: last step's shear; after turnCarriedShears: the carried shear;
                        // after springForces: the shear force of this step
  VecLanes old_normal;  // last step's normal
  // Written by springForces:
  VecLanes force;     // on A: f_n,i n_i + f_s,i
  VecLanes torque_a;  // (p_i - xA) x f_i
  VecLanes torque_b;  // (p_i - xB) x f_i (B receives minus it)
  VecLanes centre;    // f_n,i p_i
  double* normal_force = nullptr;
  double* elastic_energy = nullptr;  // kn_i g_i^2 / 2
  double* shear_energy = nullptr;    // |f_s,i|^2 / (2 ks_i)
  double* sliding = nullptr;         // 1 where the shear reached its Coulomb limit, else 0
};

/// Storage of the lane arrays, kept by the caller between pairs (nothing allocated once warm).
class SubContactLanes {
 public:
  /// Lane arrays of `lanes` entries each (rounded up to even), valid until the next call.
  SubLanes open(std::size_t lanes);

 private:
  std::vector<double> storage_;
};

/// What is the same for every sub-contact of a pair.
struct PairConstants {
  Vec3 xa, va, wa, xb, vb, wb;               // centroids and half-step velocities
  double kn = 0.0, ks = 0.0, dashpot = 0.0;  // the pair's stiffnesses, N/m; 2 zeta sqrt(m_eff Kn)
  double dt = 0.0, tan_friction = 0.0, cohesion = 0.0;
};

/// Turns every lane's shear onto its new plane: the smallest rotation of the old normal onto the
/// new (rotateShear, contact_law.h), then the rotation by the pair's mean spin about the new
/// normal over the step (spinShear, sub_contact_law.h). `half_dt` is dt / 2, `spin` (wA + wB) / 2.
void turnCarriedShears(const SubLanes& l, std::size_t lanes, const Vec3& spin, double half_dt);

/// The springs of every lane (sub_contact_law.h): normal force, the shear increment added to the
/// carried shear, the Coulomb cap, the force, both torques and the energies.
void springForces(const SubLanes& l, std::size_t lanes, const PairConstants& c);

}  // namespace polydem::dynamics
