// The free rigid body under the symplectic splitting: the asymmetric top (a 1 x 2 x 3 cuboid)
// spinning near each principal axis keeps its kinetic energy and world angular momentum, and the
// symmetric top follows the analytical torque-free precession to second order.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "polydem/dynamics/integrator.h"

namespace polydem::dynamics {
namespace {

// Cuboid 1 x 2 x 3 m of mass 12 kg: I = m (b^2 + c^2, a^2 + c^2, a^2 + b^2) / 12 = (13, 10, 5).
const Vec3 kCuboid(13.0, 10.0, 5.0);

double rotationalEnergy(const Quat& q, const Vec3& l, const Vec3& inertia) {
  const Vec3 pi = q.conjugate() * l;
  return 0.5 * pi.cwiseAbs2().cwiseQuotient(inertia).sum();
}

struct TopRun {
  double worst = 0.0;              // largest relative energy error over the run
  double worst_first_half = 0.0;   // ... over its first half
  double worst_second_half = 0.0;  // ... over its second half
  int flips = 0;                   // sign changes of the body momentum about `watch_axis`
  bool momentum_exact = true;      // world angular momentum unchanged to the bit
};

// Spins the cuboid near body axis `axis` (1 % perturbation) for `steps` steps of
// dt = spin period / steps_per_period, through advanceFree with zero torque.
TopRun spin(int axis, double steps_per_period, int steps) {
  Vec3 w = Vec3(0.01, 0.013, -0.008);
  w[axis] = 1.0;
  particles::Particle p;
  p.orientation = Quat(Eigen::AngleAxisd(0.4, Vec3(1, 2, -1).normalized()));
  const Vec3 w_world = p.orientation * w;
  p.angular_momentum = angularMomentum(p.orientation, w_world, kCuboid);
  const Vec3 l0 = p.angular_momentum;
  const MassProperties mass{12.0, kCuboid};
  const double e0 = rotationalEnergy(p.orientation, l0, kCuboid);
  const double dt = 2.0 * kPi / w.norm() / steps_per_period;
  TopRun run;
  double last_sign = 1.0;
  for (int n = 0; n < steps; ++n) {
    advanceFree(p, mass, Vec3::Zero(), Vec3::Zero(), dt, 0.0);
    const double err =
        std::abs(rotationalEnergy(p.orientation, p.angular_momentum, kCuboid) - e0) / e0;
    run.worst = std::max(run.worst, err);
    (n < steps / 2 ? run.worst_first_half : run.worst_second_half) =
        std::max(n < steps / 2 ? run.worst_first_half : run.worst_second_half, err);
    const double sign = (p.orientation.conjugate() * p.angular_momentum)[axis] >= 0.0 ? 1.0 : -1.0;
    if (sign != last_sign) ++run.flips;
    last_sign = sign;
    if (p.angular_momentum != l0) run.momentum_exact = false;
  }
  return run;
}

// Near the stable axes (largest and smallest moment), dt = 1/200 of the spin period.
TEST(RigidRotation, AsymmetricTopNearStableAxesConservesEnergy) {
  for (int axis : {0, 2}) {
    const TopRun run = spin(axis, 200.0, 100000);
    std::printf("measured: axis %d, dt = T/200, 1e5 steps: max |dE|/E = %.3e\n", axis, run.worst);
    EXPECT_LT(run.worst, 1e-6) << "axis " << axis;
    EXPECT_TRUE(run.momentum_exact) << "axis " << axis;
    EXPECT_EQ(run.flips, 0) << "axis " << axis;  // stable: the spin never reverses
  }
}

// Near the intermediate axis the body tumbles (tennis-racket effect): every component of the
// body momentum swings through large values, so the splitting error is largest. With dt = 1/1000
// of the spin period (a rotation of 6 mrad per step, still coarse for DEM, where contact stiffness
// keeps rotations per step far smaller) the energy holds to 1e-6 over 1e5 steps (100 periods).
TEST(RigidRotation, AsymmetricTopNearIntermediateAxisConservesEnergy) {
  const TopRun run = spin(1, 1000.0, 100000);
  std::printf("measured: intermediate axis, dt = T/1000, 1e5 steps: max |dE|/E = %.3e, %d flips\n",
              run.worst, run.flips);
  EXPECT_GE(run.flips, 2);  // it does tumble
  EXPECT_LT(run.worst, 1e-6);
  EXPECT_TRUE(run.momentum_exact);
}

// The energy error is bounded (no drift) and second-order: halving dt divides it by 4.
TEST(RigidRotation, EnergyErrorIsSecondOrderWithoutDrift) {
  const TopRun coarse = spin(1, 200.0, 40000);  // 200 periods
  const TopRun fine = spin(1, 400.0, 80000);    // the same 200 periods
  const double ratio = coarse.worst / fine.worst;
  std::printf(
      "measured: intermediate axis, T/200: %.3e (halves %.3e, %.3e), T/400: %.3e, ratio %.3f\n",
      coarse.worst, coarse.worst_first_half, coarse.worst_second_half, fine.worst, ratio);
  EXPECT_NEAR(ratio, 4.0, 0.4);
  // The tumbling repeats; the error over the second half is no larger than over the first.
  EXPECT_LT(coarse.worst_second_half, 1.05 * coarse.worst_first_half);
  EXPECT_LT(fine.worst_second_half, 1.05 * fine.worst_first_half);
}

// Torque-free symmetric top (I1 = I2): H = |pi|^2 / (2 I1) + (1/I3 - 1/I1) pi_3^2 / 2, two
// commuting exact flows, so Q(t) = R(L/|L|, |L| t / I1) Q0 R(e3, (1/I3 - 1/I1) pi_3 t): the
// symmetry axis precesses about L at |L| / I1 while the body spins about it.
Quat symmetricTop(const Quat& q0, const Vec3& l, const Vec3& inertia, double t) {
  const double pi3 = (q0.conjugate() * l).z();
  const Quat precession(Eigen::AngleAxisd(l.norm() / inertia.x() * t, l.normalized()));
  const Quat spin_about_axis(
      Eigen::AngleAxisd((1.0 / inertia.z() - 1.0 / inertia.x()) * pi3 * t, Vec3::UnitZ()));
  return precession * q0 * spin_about_axis;
}

double angleBetween(const Quat& a, const Quat& b) {
  const double c = std::min(1.0, std::abs(a.dot(b)));
  return 2.0 * std::acos(c);
}

// Largest orientation error over `periods` spin periods at dt = period / steps_per_period.
double precessionError(const Vec3& inertia, double steps_per_period, int periods) {
  const Quat q0(Eigen::AngleAxisd(0.9, Vec3(0.3, -1, 0.2).normalized()));
  const Vec3 w_body(0.6, -0.2, 1.3);  // well off the symmetry axis: a wide precession cone
  const Vec3 l = q0 * w_body.cwiseProduct(inertia);
  const double period = 2.0 * kPi / w_body.norm();
  const double dt = period / steps_per_period;
  Quat q = q0;
  double worst = 0.0;
  const int steps = static_cast<int>(steps_per_period) * periods;
  for (int n = 1; n <= steps; ++n) {
    q = freeRotation(q, l, inertia, dt);
    worst = std::max(worst, angleBetween(q, symmetricTop(q0, l, inertia, n * dt)));
  }
  return worst;
}

TEST(RigidRotation, SymmetricTopFollowsTheAnalyticalPrecession) {
  for (const Vec3& inertia : {Vec3(2.0, 2.0, 3.0), Vec3(2.0, 2.0, 0.7)}) {
    const double coarse = precessionError(inertia, 200.0, 20);
    const double fine = precessionError(inertia, 400.0, 20);
    std::printf(
        "measured: symmetric top I = (%g %g %g), 20 periods: error %.3e rad (T/200), %.3e rad "
        "(T/400)\n",
        inertia.x(), inertia.y(), inertia.z(), coarse, fine);
    // Second order: the error of a given time span shrinks 4x when dt is halved.
    EXPECT_NEAR(coarse / fine, 4.0, 0.3) << inertia.transpose();
    // A phase error of O((w dt)^2) per unit angle turned: over 20 periods (40 pi rad) at
    // w dt = 2 pi / 200 that is of order 40 pi (w dt)^2 = 0.12 rad; the splitting does better.
    const double wdt = 2.0 * kPi / 200.0;
    EXPECT_LT(coarse, 40.0 * kPi * wdt * wdt) << inertia.transpose();
  }
}

}  // namespace
}  // namespace polydem::dynamics
