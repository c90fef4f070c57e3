// Kinematic drivers: a platform tilting about a hinge (Zhao section 5.3: 0.03 rad/s), a shaken
// base following a sinusoid, and the material-point velocity the contact law uses.
#include "polydem/dynamics/driver.h"

#include <gtest/gtest.h>

#include <cmath>

namespace polydem::dynamics {
namespace {

// The platform turns about a hinge along y through `pivot`: after t it has turned by 0.03 t, its
// hinge line has not moved, and each of its points has turned about the hinge.
TEST(Driver, TiltingPlatformTurnsAboutAFixedHinge) {
  for (double scale : {1.0, 1e-3, 1e3}) {  // the same motion in m, km or mm
    DriverSpec d;
    d.angular_velocity = Vec3(0, 0.03, 0);
    d.pivot = scale * Vec3(2.0, 0.0, -1.0);
    particles::Particle p;
    p.flags = particles::kDriven;
    p.position = scale * Vec3(3.5, 0.4, -0.75);  // centroid of the platform
    p.orientation = Quat(Eigen::AngleAxisd(0.1, Vec3::UnitZ()));
    const Vec3 x0 = p.position;
    const Quat q0 = p.orientation;
    // Two points of the hinge line, in body coordinates.
    const Vec3 hinge_a = q0.conjugate() * (d.pivot - x0);
    const Vec3 hinge_b = q0.conjugate() * (d.pivot + scale * Vec3(0, 1.7, 0) - x0);
    const double dt = 1e-3;
    const int steps = 15000;  // 15 s: 0.45 rad = 25.8 deg
    for (int n = 0; n < steps; ++n) advanceDriven(p, d, n * dt, dt);
    const double t = steps * dt;
    const Quat turn(Eigen::AngleAxisd(0.03 * t, Vec3::UnitY()));
    const double tol = 1e-12 * scale;
    EXPECT_NEAR((p.position - (d.pivot + turn * (x0 - d.pivot))).norm(), 0.0, tol) << scale;
    EXPECT_NEAR((p.orientation * q0.conjugate()).angularDistance(turn), 0.0, 1e-12);
    // The tilt angle, read back from the orientation.
    const Eigen::AngleAxisd tilt(p.orientation * q0.conjugate());
    EXPECT_NEAR(tilt.angle(), 0.45, 1e-12);
    EXPECT_NEAR(std::abs(tilt.axis().y()), 1.0, 1e-12);
    // The hinge stays where it was.
    EXPECT_NEAR((p.position + p.orientation * hinge_a - d.pivot).norm(), 0.0, tol) << scale;
    EXPECT_NEAR((p.position + p.orientation * hinge_b - (d.pivot + scale * Vec3(0, 1.7, 0))).norm(),
                0.0, tol)
        << scale;
    // Stepping agrees with the closed form.
    const Pose closed = drivenPose(d, Pose{x0, q0}, 0.0, t);
    EXPECT_NEAR((closed.position - p.position).norm(), 0.0, tol);
    EXPECT_NEAR(closed.orientation.angularDistance(p.orientation), 0.0, 1e-12);
    // The velocity is the centroid's at the half step: w x (x(t - dt/2) - pivot).
    const Vec3 x_half =
        d.pivot + Quat(Eigen::AngleAxisd(0.03 * (t - 0.5 * dt), Vec3::UnitY())) * (x0 - d.pivot);
    EXPECT_NEAR((p.velocity - d.angular_velocity.cross(x_half - d.pivot)).norm(), 0.0, tol);
  }
}

// Shaken base: v(t) = a sin(2 pi f (t - t0) + phase) between t0 and t1, so
// x(t) = x0 + a (cos(phase) - cos(2 pi f (t - t0) + phase)) / (2 pi f), and still outside.
TEST(Driver, ShakenBaseFollowsTheSinusoid) {
  DriverSpec d;
  d.oscillation = Vec3(0.05, 0.0, 0.02);
  d.frequency = 5.0;
  d.phase = 0.7;
  d.start_time = 0.3;
  d.end_time = 1.5;
  d.velocity = Vec3(0.0, 0.01, 0.0);
  const double omega = 2.0 * kPi * d.frequency;
  auto displacement = [&](double t) {
    const double s = std::clamp(t, d.start_time, d.end_time);
    return Vec3(d.velocity * (s - d.start_time) +
                d.oscillation *
                    (std::cos(d.phase) - std::cos(omega * (s - d.start_time) + d.phase)) / omega);
  };
  particles::Particle p;
  p.flags = particles::kDriven;
  const Vec3 x0(1.0, 2.0, 3.0);
  p.position = x0;
  const double dt = 1e-4;
  for (int n = 0; n < 20000; ++n) {
    const double t = n * dt;
    advanceDriven(p, d, t, dt);
    ASSERT_NEAR((p.position - (x0 + displacement(t + dt))).norm(), 0.0, 1e-13) << "step " << n;
    const double mid = t + 0.5 * dt;
    if (mid > d.start_time && mid < d.end_time) {
      const Vec3 v = d.velocity + d.oscillation * std::sin(omega * (mid - d.start_time) + d.phase);
      ASSERT_NEAR((p.velocity - v).norm(), 0.0, 1e-13) << "step " << n;
    } else {
      ASSERT_EQ(p.velocity, Vec3::Zero()) << "step " << n;
    }
    ASSERT_EQ(p.orientation.coeffs(), Quat::Identity().coeffs());
  }
}

TEST(Driver, StateOutsideTheWindowIsAtRest) {
  DriverSpec d;
  d.velocity = Vec3(1, 0, 0);
  d.angular_velocity = Vec3(0, 0, 0.5);
  d.pivot = Vec3(0, 0, 1);
  d.start_time = 1.0;
  d.end_time = 3.0;
  const DriverState before = driverState(d, 0.5);
  EXPECT_EQ(before.velocity, Vec3::Zero());
  EXPECT_EQ(before.angular_velocity, Vec3::Zero());
  EXPECT_EQ(before.pivot, d.pivot);
  const DriverState during = driverState(d, 2.0);
  EXPECT_EQ(during.velocity, d.velocity);
  EXPECT_EQ(during.angular_velocity, d.angular_velocity);
  EXPECT_NEAR((during.pivot - Vec3(1, 0, 1)).norm(), 0.0, 1e-15);
  const DriverState after = driverState(d, 10.0);
  EXPECT_EQ(after.velocity, Vec3::Zero());
  EXPECT_NEAR((after.pivot - Vec3(2, 0, 1)).norm(), 0.0, 1e-15);
  EXPECT_DOUBLE_EQ(activeTime(d, 0.0, 10.0), 2.0);
  EXPECT_DOUBLE_EQ(activeTime(d, 2.5, 2.75), 0.25);
  EXPECT_EQ(activeTime(d, 4.0, 5.0), 0.0);
}

// The velocity field v + w x (x - P) is the time derivative of the material points' positions,
// for a motion that combines translation, oscillation and rotation about the moving pivot.
TEST(Driver, MaterialPointVelocityIsTheDerivativeOfThePosition) {
  DriverSpec d;
  d.velocity = Vec3(0.2, -0.1, 0.05);
  d.oscillation = Vec3(0.0, 0.3, 0.1);
  d.frequency = 2.0;
  d.phase = 0.3;
  d.angular_velocity = Vec3(0.1, 0.4, -0.2);
  d.pivot = Vec3(1.0, 0.0, -2.0);
  const Pose pose0{Vec3(0.5, 1.5, -1.0), Quat(Eigen::AngleAxisd(0.2, Vec3(1, 1, 0).normalized()))};
  const Vec3 body_point(0.3, -0.7, 0.4);  // a material point, body frame
  auto world = [&](double t) {
    const Pose pose = drivenPose(d, pose0, 0.0, t);
    return Vec3(pose.position + pose.orientation * body_point);
  };
  for (double t : {0.25, 0.8, 1.7}) {
    const double h = 1e-5;
    const Vec3 derivative = (world(t + h) - world(t - h)) / (2.0 * h);
    const Vec3 field = materialPointVelocity(driverState(d, t), world(t));
    // Central difference: O(h^2 |d3x/dt3|) ~ 1e-10, plus round-off 1e-16 / h ~ 1e-11.
    EXPECT_NEAR((field - derivative).norm(), 0.0, 1e-8) << "t = " << t;
  }
}

}  // namespace
}  // namespace polydem::dynamics
