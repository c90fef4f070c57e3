// The force law of a rock bolt or cable at one joint it crosses (docs/scene-format.md "Rock
// bolts"), after the local bolt model of 3DEC's cable and rockbolt elements: the relative
// displacement du of the two blocks at the bolt's crossing point is split into the axial part
// du . a (a: the bolt's unit axis, pointing from the first block into the second) and the shear
// part du - (du . a) a, and each drives an elastic-perfectly plastic spring:
//
//   axial   N = pretension + k_a (u_a - u_a^p),   |N| <= N_y   (tension positive; compression is
//           capped at the same yield force: a grouted bar yields both ways)
//   shear   S = k_s (u_s - u_s^p),                |S| <= S_y
//
// where u^p is the plastic slip, kept as state so that unloading is elastic. The bolt breaks at
// that joint, for good, when its plastic elongation u_a^p reaches the ultimate elongation; a broken
// joint carries nothing from then on.
#pragma once

#include <limits>

#include "polydem/core/types.h"

namespace polydem::dynamics {

struct BoltLaw {
  double axial_stiffness = 0.0;                                          // k_a, N/m
  double axial_yield = 0.0;                                              // N_y, N
  double shear_stiffness = 0.0;                                          // k_s, N/m
  double shear_yield = 0.0;                                              // S_y, N
  double pretension = 0.0;                                               // N at zero displacement
  double ultimate_elongation = std::numeric_limits<double>::infinity();  // m of plastic u_a^p
};

/// The state one bolt keeps at one joint.
struct BoltJointState {
  double axial_plastic = 0.0;         // u_a^p, m (elongation positive)
  Vec3 shear_plastic = Vec3::Zero();  // u_s^p, m, world frame
  bool broken = false;
};

struct BoltJointForce {
  double axial = 0.0;         // N, tension positive
  Vec3 shear = Vec3::Zero();  // N, world frame: the force on the first block; minus on the second
  bool broke_now = false;     // the bolt broke at this joint in this call
  /// The force on the first block (the second takes minus it): tension pulls the first block
  /// along the axis towards the second, the shear spring resists the relative slip.
  Vec3 onFirst(const Vec3& axis) const { return axial * axis + shear; }
};

/// The bolt force at a joint for the relative displacement `du` (of the second block's anchor
/// point against the first's) along unit `axis`; updates the plastic slips and the broken flag.
BoltJointForce boltJointForce(const BoltLaw& law, const Vec3& axis, const Vec3& du,
                              BoltJointState& state);

}  // namespace polydem::dynamics
