// Kinematic drivers: particles moved as prescribed (a tilting platform, a shaken base), never by
// forces. A driver (DriverSpec, driver_spec.h) gives, while it is active (start_time <= t <=
// end_time),
//   v(t) = velocity + oscillation sin(2 pi frequency (t - start_time) + phase),   w(t) = w,
// and nothing outside that window. The pivot P moves with v (P = DriverSpec::pivot at start_time).
// The velocity field of the body is u(x, t) = v(t) + w x (x - P(t)); relative to the pivot,
// points turn about w: x(t) - P(t) = R(w tau) (x0 - P0), tau the active time since t0. Every
// function here is exact for that motion (closed-form integrals of v, exact rotations), so a
// driven body shows no drift however many steps it takes.
#pragma once

#include "polydem/core/types.h"
#include "polydem/dynamics/driver_spec.h"
#include "polydem/particles/particle.h"

namespace polydem::dynamics {

/// The driver's motion at one instant.
struct DriverState {
  Vec3 velocity = Vec3::Zero();          // v(t), of the pivot
  Vec3 angular_velocity = Vec3::Zero();  // w(t)
  Vec3 pivot = Vec3::Zero();             // P(t)
};

/// v(t), w(t) and P(t) of `driver` at time t.
DriverState driverState(const DriverSpec& driver, double t);

/// Velocity of the material point of the driven body that is at x at the time of `state`:
/// v + w x (x - P). The contact law's v_rel uses it for a driven partner; to match the free
/// particles' leapfrog velocities (taken at t - dt/2) call driverState(driver, t - dt/2).
inline Vec3 materialPointVelocity(const DriverState& state, const Vec3& x) {
  return state.velocity + state.angular_velocity.cross(x - state.pivot);
}

/// Time during which the driver is active within [t0, t1] (t0 <= t1).
double activeTime(const DriverSpec& driver, double t0, double t1);

/// Displacement of the pivot from t0 to t1: the exact integral of v(t) (t0 <= t1).
Vec3 pivotDisplacement(const DriverSpec& driver, double t0, double t1);

struct Pose {
  Vec3 position = Vec3::Zero();
  Quat orientation = Quat::Identity();
};

/// The pose at time t of a driven body that had `pose0` at time t0 <= t (e.g. the scene's
/// initial pose at t = 0): closed form, no accumulation of round-off over steps.
Pose drivenPose(const DriverSpec& driver, const Pose& pose0, double t0, double t);

/// Advances a driven particle from t to t + dt exactly: position and orientation turned by
/// R(w tau) about the pivot while the pivot moves by its exact displacement (tau: the active part
/// of the step). Pre: p.isDriven(), dt > 0. Post: p.position, p.orientation at t + dt (the
/// quaternion renormalised); p.velocity is the velocity of the centroid at t + dt/2, the same
/// half-step convention as free particles. p.angular_momentum is not used for driven particles
/// and is left as it is: their angular velocity is the driver's w (see ParticleStorage).
void advanceDriven(particles::Particle& p, const DriverSpec& driver, double t, double dt);

}  // namespace polydem::dynamics
