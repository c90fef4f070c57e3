// Time integration of free rigid bodies: the leapfrog (velocities at half steps) for translation
// and angular momentum, and a symplectic splitting of the free rigid body for the orientation.
//
// State (particles/particle.h): position x and orientation q at time t; velocity v and world
// angular momentum L at t - dt/2. One step with the force F and torque T evaluated at time t:
//   v <- v + dt F / m                      x <- x + dt v
//   L <- L + dt T                          q <- free rotation of q over dt with L held fixed
// The free rotation splits the kinetic energy H = sum_k pi_k^2 / (2 I_k) (pi = body-frame angular
// momentum, I_k principal moments) into three exactly solvable parts, each a rotation of the body
// about one principal axis by the angle h pi_k / I_k, composed as the Strang sequence
//   1(h/2) 2(h/2) 3(h) 2(h/2) 1(h/2),   axes 1, 2, 3 by increasing principal moment
// (Dullweber, Leimkuhler & McLachlan, J. Chem. Phys. 107, 5840 (1997), "symplectic splitting").
// Each part is the exact flow of a Hamiltonian, so the step is symplectic, time-reversible and
// second-order; L stays exactly fixed in the world during the flight (it is never written by the
// rotation), and the kinetic energy has a bounded O(h^2) error without drift. See docs/dynamics.md.
//
// Gravity is not added here: the caller passes the total force (contacts + m g).
#pragma once

#include "polydem/core/types.h"
#include "polydem/particles/particle.h"

namespace polydem::dynamics {

struct MassProperties {
  double mass = 0.0;                      // kg
  Vec3 principal_inertia = Vec3::Zero();  // kg m^2, principal moments about the body axes
};

/// Angular velocity (world) of a body of orientation q (body -> world) and world angular
/// momentum L: w = R I^-1 R^T L.
Vec3 angularVelocity(const Quat& q, const Vec3& angular_momentum, const Vec3& principal_inertia);

/// World angular momentum of a body turning at world angular velocity w: L = R I R^T w.
Vec3 angularMomentum(const Quat& q, const Vec3& angular_velocity, const Vec3& principal_inertia);

/// Local non-viscous damping of 3DEC / PFC ("local damping"): each world component of the force
/// is reduced by a fraction alpha of its magnitude against the velocity's component,
///   F_i - alpha |F_i| sign(v_i),   sign(0) = 0,
/// so that damping removes energy whatever the direction of motion and vanishes at rest. The same
/// form damps a torque with the angular velocity. Pre: 0 <= alpha < 1.
Vec3 localDamping(const Vec3& force, const Vec3& velocity, double alpha);

/// The orientation after a torque-free flight of duration h with the world angular momentum L
/// held fixed: the symplectic splitting above. The result is renormalised. Pre: principal moments
/// > 0, q a unit quaternion (body -> world).
Quat freeRotation(const Quat& q, const Vec3& angular_momentum, const Vec3& principal_inertia,
                  double h);

/// One leapfrog step of a free particle from t to t + dt (see the top of the file).
/// Pre:  `force` and `torque` (about the centroid) are the totals on the particle at time t, world
///       frame, gravity included, summed in a fixed order; p.velocity and p.angular_momentum are
///       at t - dt/2; 0 <= local_damping < 1 (the particle's material value, or the stage's).
/// Post: p.position, p.orientation at t + dt; p.velocity, p.angular_momentum at t + dt/2.
///       Local damping, when alpha > 0, uses the velocities at t - dt/2 (3DEC practice).
///       Fixed and driven particles are left untouched (drivers move the latter, see driver.h).
/// Throws SimulationError naming the uid if the force or torque is not finite.
void advanceFree(particles::Particle& p, const MassProperties& mass, const Vec3& force,
                 const Vec3& torque, double dt, double local_damping);

/// Starts the leapfrog: turns velocities given at t = 0 (as a scene gives them) into the half-step
/// velocities at -dt/2 with the forces at t = 0, v <- v - dt/2 F/m and L <- L - dt/2 T (no
/// damping). Without it, positions carry an O(dt) offset (x gains a dt t / 2 under a constant
/// acceleration a). Fixed and driven particles are left untouched.
void startLeapfrog(particles::Particle& p, const MassProperties& mass, const Vec3& force,
                   const Vec3& torque, double dt);

}  // namespace polydem::dynamics
