#include "polydem/dynamics/driver.h"

#include <algorithm>
#include <cmath>

namespace polydem::dynamics {

namespace {

bool active(const DriverSpec& d, double t) {
  return t >= d.start_time && t <= d.end_time;
}

// Rotation by the vector `angle` (axis * angle in rad); the identity for a zero vector.
Quat rotationBy(const Vec3& angle) {
  const double a = angle.norm();
  if (a == 0.0) return Quat::Identity();
  return Quat(Eigen::AngleAxisd(a, angle / a));
}

}  // namespace

double activeTime(const DriverSpec& d, double t0, double t1) {
  return std::max(0.0, std::min(t1, d.end_time) - std::max(t0, d.start_time));
}

Vec3 pivotDisplacement(const DriverSpec& d, double t0, double t1) {
  const double a = std::max(t0, d.start_time), b = std::min(t1, d.end_time);
  if (!(b > a)) return Vec3::Zero();
  Vec3 out = d.velocity * (b - a);
  if (d.frequency == 0.0) {
    out += d.oscillation * (std::sin(d.phase) * (b - a));
  } else {
    // integral of sin(omega s + phase) over [a, b] = (cos(theta_a) - cos(theta_b)) / omega,
    // written as 2 sin(mean) sin(half width) / omega to avoid cancellation over short steps.
    const double omega = 2.0 * kPi * d.frequency;
    const double mean = 0.5 * omega * ((a - d.start_time) + (b - d.start_time)) + d.phase;
    const double half = 0.5 * omega * (b - a);
    out += d.oscillation * (2.0 * std::sin(mean) * std::sin(half) / omega);
  }
  return out;
}

DriverState driverState(const DriverSpec& d, double t) {
  DriverState s;
  s.pivot = d.pivot + pivotDisplacement(d, d.start_time, t);
  if (active(d, t)) {
    s.velocity = d.velocity +
                 d.oscillation * std::sin(2.0 * kPi * d.frequency * (t - d.start_time) + d.phase);
    s.angular_velocity = d.angular_velocity;
  }
  return s;
}

Pose drivenPose(const DriverSpec& d, const Pose& pose0, double t0, double t) {
  const Quat turn = rotationBy(d.angular_velocity * activeTime(d, t0, t));
  const Vec3 pivot0 = d.pivot + pivotDisplacement(d, d.start_time, t0);
  const Vec3 pivot = pivot0 + pivotDisplacement(d, t0, t);
  Pose out;
  out.position = pivot + turn * (pose0.position - pivot0);
  out.orientation = (turn * pose0.orientation).normalized();
  return out;
}

void advanceDriven(particles::Particle& p, const DriverSpec& d, double t, double dt) {
  const Pose now{p.position, p.orientation};
  const Pose mid = drivenPose(d, now, t, t + 0.5 * dt);
  p.velocity = materialPointVelocity(driverState(d, t + 0.5 * dt), mid.position);
  const Pose next = drivenPose(d, now, t, t + dt);
  p.position = next.position;
  p.orientation = next.orientation;
}

}  // namespace polydem::dynamics
