// The leapfrog on problems with exact discrete and continuous answers: constant force, constant
// torque, the mass-spring oscillator (period, energy), local damping, fixed particles.
#include "polydem/dynamics/integrator.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "polydem/core/error.h"

namespace polydem::dynamics {
namespace {

particles::Particle freeParticle() {
  particles::Particle p;
  p.uid = 7;
  return p;
}

const MassProperties kBox{3.0, Vec3(1.0, 2.0, 2.5)};

// Under a constant force the leapfrog is exact once started half a step back: x(t) is the
// parabola x0 + v0 t + a t^2 / 2. Started without the half step (v given at t = 0 used as
// v(-dt/2)) it gains exactly a dt t / 2, the leapfrog's known offset.
TEST(Integrator, ConstantForceFollowsTheParabola) {
  const Vec3 x0(1.0, -2.0, 0.5), v0(0.3, 0.0, 4.0), force(0.6, -1.5, -29.43);
  const Vec3 a = force / kBox.mass;
  const double dt = 1e-3;
  const int steps = 4000;
  for (bool started : {true, false}) {
    particles::Particle p = freeParticle();
    p.position = x0;
    p.velocity = v0;
    if (started) startLeapfrog(p, kBox, force, Vec3::Zero(), dt);
    for (int n = 1; n <= steps; ++n) {
      advanceFree(p, kBox, force, Vec3::Zero(), dt, 0.0);
      const double t = n * dt;
      Vec3 expected = x0 + v0 * t + 0.5 * a * t * t;
      if (!started) expected += 0.5 * a * dt * t;
      ASSERT_NEAR((p.position - expected).norm(), 0.0, 1e-12 * (1.0 + expected.norm()))
          << "step " << n << (started ? " (started)" : " (not started)");
      // The velocity is now taken at t - dt/2 (started) or carries the same offset (not started).
      const Vec3 v_expected = v0 + a * (started ? t - 0.5 * dt : t);
      ASSERT_NEAR((p.velocity - v_expected).norm(), 0.0, 1e-12 * (1.0 + v_expected.norm()));
    }
  }
}

// L(t) = L0 + T t: with binary-exact data every addition is exact, so equality is demanded.
TEST(Integrator, ConstantTorqueGivesLinearAngularMomentum) {
  particles::Particle p = freeParticle();
  const Vec3 l0(0.5, 0.25, -1.0), torque(2.0, -1.0, 0.5);
  const double dt = 1.0 / 1024.0;
  p.angular_momentum = l0;
  for (int n = 1; n <= 10000; ++n) {
    advanceFree(p, kBox, Vec3::Zero(), torque, dt, 0.0);
    ASSERT_EQ(p.angular_momentum, Vec3(l0 + torque * (n * dt))) << "step " << n;
    ASSERT_NEAR(p.orientation.norm(), 1.0, 1e-15);
  }
}

// x'' = -w^2 x. The leapfrog's discrete frequency is w~ with sin(w~ dt / 2) = w dt / 2, so its
// period is 2 pi / w~ = (2 pi / w)(1 - (w dt)^2 / 24 + ...); it conserves the shadow energy
// m v(n-1/2) v(n+1/2) / 2 + k x(n)^2 / 2 exactly, and the plain energy to O((w dt)^2) without
// drift.
TEST(Integrator, MassSpringHasTheRightPeriodAndNoEnergyDrift) {
  const double m = 2.5, k = 4.0e4, w = std::sqrt(k / m);
  const double period = 2.0 * kPi / w;
  const double dt = period / 100.0;
  const MassProperties mass{m, Vec3::Ones()};
  particles::Particle p = freeParticle();
  const double amplitude = 0.01;
  p.position = Vec3(amplitude, 0, 0);
  startLeapfrog(p, mass, Vec3(-k * amplitude, 0, 0), Vec3::Zero(), dt);

  const int steps = 100000;  // 1000 periods
  std::vector<double> up_crossings;
  double shadow0 = 0.0, worst_shadow = 0.0;
  double energy_first = 0.0, energy_last = 0.0;  // largest deviation in the first/last 10 periods
  const double e0 = 0.5 * k * amplitude * amplitude;
  for (int n = 0; n < steps; ++n) {
    const double x = p.position.x();
    const double v_before = p.velocity.x();
    advanceFree(p, mass, Vec3(-k * x, 0, 0), Vec3::Zero(), dt, 0.0);
    const double v_after = p.velocity.x();
    const double shadow = 0.5 * m * v_before * v_after + 0.5 * k * x * x;
    if (n == 0) shadow0 = shadow;
    worst_shadow = std::max(worst_shadow, std::abs(shadow - shadow0) / shadow0);
    const double energy = 0.5 * m * v_after * v_after + 0.5 * k * x * x;
    if (n < 1000) energy_first = std::max(energy_first, std::abs(energy - e0) / e0);
    if (n >= steps - 1000) energy_last = std::max(energy_last, std::abs(energy - e0) / e0);
    const double x_next = p.position.x();
    if (x < 0.0 && x_next >= 0.0) up_crossings.push_back((n + x / (x - x_next)) * dt);
  }
  ASSERT_GT(up_crossings.size(), 900u);
  const double measured =
      (up_crossings.back() - up_crossings.front()) / double(up_crossings.size() - 1);
  const double discrete = 2.0 * kPi / (2.0 / dt * std::asin(0.5 * w * dt));
  std::printf(
      "measured: period %.12e, discrete %.12e, analytical %.12e; energy %.3e / %.3e; shadow %.3e\n",
      measured, discrete, period, energy_first, energy_last, worst_shadow);
  EXPECT_NEAR(measured, discrete, 1e-9 * period);
  // The analytical period, to the leapfrog's second-order error (w dt)^2 / 24 ~ 1.6e-4 here.
  const double wdt = w * dt;
  EXPECT_NEAR(measured, period, 1.05 * wdt * wdt / 24.0 * period);
  EXPECT_LT(worst_shadow, 1e-12);
  // Plain energy (velocity half a step off): an O(w dt) oscillation, as large at the end as at the
  // start. Sampling the peak of that oscillation at steps of w dt changes it by O((w dt)^2 / 2).
  EXPECT_LT(energy_first, wdt);
  EXPECT_NEAR(energy_last / energy_first, 1.0, wdt * wdt);
}

TEST(Integrator, LocalDampingFormPerComponent) {
  const Vec3 f(2.0, -3.0, 4.0), v(1.0, 1.0, 0.0);
  const Vec3 d = localDamping(f, v, 0.25);
  EXPECT_DOUBLE_EQ(d.x(), 2.0 - 0.25 * 2.0);   // force along the motion: reduced
  EXPECT_DOUBLE_EQ(d.y(), -3.0 - 0.25 * 3.0);  // force against the motion: increased
  EXPECT_DOUBLE_EQ(d.z(), 4.0);                // no motion: untouched
}

// With local damping alpha a spring is stiffer (k(1 + alpha)) on the way out and softer
// (k(1 - alpha)) on the way back, so each half cycle multiplies the amplitude by
// sqrt((1 - alpha) / (1 + alpha)), independently of the amplitude (3DEC local damping).
TEST(Integrator, LocalDampingDecaysAnOscillatorAsPredicted) {
  const double m = 1.0, k = 1.0e4, alpha = 0.1;
  const double dt = 2.0 * kPi * std::sqrt(m / k) / 4000.0;
  const MassProperties mass{m, Vec3::Ones()};
  particles::Particle p = freeParticle();
  p.position = Vec3(1e-2, 0, 0);
  std::vector<double> peaks;
  double previous = p.position.x(), before = previous;
  for (int n = 0; n < 40000 && peaks.size() < 8; ++n) {
    advanceFree(p, mass, Vec3(-k * p.position.x(), 0, 0), Vec3::Zero(), dt, alpha);
    const double x = p.position.x();
    if (n > 1 && std::abs(previous) >= std::abs(before) && std::abs(previous) > std::abs(x)) {
      peaks.push_back(std::abs(previous));
    }
    before = previous;
    previous = x;
  }
  ASSERT_EQ(peaks.size(), 8u);
  const double ratio = std::sqrt((1.0 - alpha) / (1.0 + alpha));
  for (std::size_t i = 1; i < peaks.size(); ++i) {
    std::printf("measured: half cycle %zu peak ratio %.12f (predicted %.12f)\n", i,
                peaks[i] / peaks[i - 1], ratio);
  }
  // Peaks are sampled at whole steps and the damping switches sign one step late at a turning
  // point, where the velocity is O(w dt) of its maximum: both are O((w dt)^2) = 2.5e-6 here.
  const double wdt = std::sqrt(k / m) * dt;
  for (std::size_t i = 1; i < peaks.size(); ++i) {
    EXPECT_NEAR(peaks[i] / peaks[i - 1], ratio, wdt * wdt) << "half cycle " << i;
  }
}

TEST(Integrator, FixedAndDrivenParticlesDoNotMove) {
  for (std::uint32_t flag : {particles::kFixed, particles::kDriven}) {
    particles::Particle p = freeParticle();
    p.flags = flag;
    p.position = Vec3(1, 2, 3);
    p.velocity = Vec3(4, 5, 6);
    const particles::Particle before = p;
    advanceFree(p, kBox, Vec3(1e6, 1e6, 1e6), Vec3(1e6, 0, 0), 1e-3, 0.5);
    startLeapfrog(p, kBox, Vec3(1e6, 1e6, 1e6), Vec3(1e6, 0, 0), 1e-3);
    EXPECT_EQ(p.position, before.position);
    EXPECT_EQ(p.velocity, before.velocity);
    EXPECT_EQ(p.angular_momentum, before.angular_momentum);
    EXPECT_EQ(p.orientation.coeffs(), before.orientation.coeffs());
  }
}

TEST(Integrator, NonFiniteForceNamesTheParticle) {
  particles::Particle p = freeParticle();
  try {
    advanceFree(p, kBox, Vec3(std::nan(""), 0, 0), Vec3::Zero(), 1e-3, 0.0);
    FAIL() << "no exception";
  } catch (const SimulationError& e) {
    EXPECT_NE(std::string(e.what()).find("particle 7"), std::string::npos) << e.what();
  }
}

TEST(Integrator, AngularVelocityAndMomentumAreInverse) {
  const Quat q(Eigen::AngleAxisd(0.7, Vec3(1, -2, 0.5).normalized()));
  const Vec3 inertia(0.4, 1.1, 2.3), w(0.3, -1.2, 2.0);
  const Vec3 l = angularMomentum(q, w, inertia);
  EXPECT_NEAR((angularVelocity(q, l, inertia) - w).norm(), 0.0, 1e-14 * w.norm());
  const Mat3 r = q.toRotationMatrix();
  const Mat3 world_inertia = r * inertia.asDiagonal() * r.transpose();
  EXPECT_NEAR((l - world_inertia * w).norm(), 0.0, 1e-14 * l.norm());
}

}  // namespace
}  // namespace polydem::dynamics
