// Elastic-perfectly plastic axial and shear springs of a bolt at a joint (bolt_law.h).
#include "polydem/dynamics/bolt_law.h"

#include <cmath>

namespace polydem::dynamics {

namespace {

// Axial: a trial force from the elastic spring, returned onto the yield force with the excess
// going into plastic elongation (or shortening).
double axialForce(const BoltLaw& law, double u_axial, BoltJointState& state) {
  const double trial = law.pretension + law.axial_stiffness * (u_axial - state.axial_plastic);
  if (trial > law.axial_yield) {
    state.axial_plastic += (trial - law.axial_yield) / law.axial_stiffness;
    return law.axial_yield;
  }
  if (trial < -law.axial_yield) {
    state.axial_plastic += (trial + law.axial_yield) / law.axial_stiffness;
    return -law.axial_yield;
  }
  return trial;
}

// Shear: the spring force resists the relative slip (it acts on the first block along +slip);
// beyond the yield force the excess slip becomes plastic, in the direction of the trial force.
Vec3 shearForce(const BoltLaw& law, const Vec3& axis, const Vec3& u_shear, BoltJointState& state) {
  if (!(law.shear_stiffness > 0.0)) return Vec3::Zero();
  const Vec3 plastic = state.shear_plastic - state.shear_plastic.dot(axis) * axis;
  const Vec3 trial = law.shear_stiffness * (u_shear - plastic);
  const double size = trial.norm();
  if (size <= law.shear_yield) return trial;
  const Vec3 dir = trial / size;
  state.shear_plastic = plastic + ((size - law.shear_yield) / law.shear_stiffness) * dir;
  return law.shear_yield * dir;
}

}  // namespace

BoltJointForce boltJointForce(const BoltLaw& law, const Vec3& axis, const Vec3& du,
                              BoltJointState& state) {
  BoltJointForce f;
  if (state.broken) return f;
  const double u_axial = du.dot(axis);
  f.axial = axialForce(law, u_axial, state);
  if (state.axial_plastic >= law.ultimate_elongation) {
    state.broken = true;
    f.broke_now = true;
    f.axial = 0.0;
    return f;
  }
  f.shear = shearForce(law, axis, du - u_axial * axis, state);
  return f;
}

}  // namespace polydem::dynamics
