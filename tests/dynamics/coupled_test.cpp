// The contact law and the integrator together on one-degree-of-freedom problems with a synthetic
// contact (fixed normal, depth from the position): a block sliding on an incline (the physics of
// D-SLIDING-BLOCK, Zhao section 5.2, eqs. 41-42) and a block bouncing on a viscously damped
// contact (the damped oscillator). Only translation is integrated, as the analytical answers
// assume.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "polydem/dynamics/contact_law.h"
#include "polydem/dynamics/integrator.h"

namespace polydem::dynamics {
namespace {

constexpr double kG = 9.81;

// A block A on a fixed plane B through the origin with unit normal n (B into A). The depth is read
// from the block's centroid: depth = depth0 - (x - x0) . n.
struct BlockOnPlane {
  Vec3 n;
  double depth0 = 0.0;
  Vec3 x0 = Vec3::Zero();
  MassProperties mass;
  LawCoefficients law;
  Vec3 gravity = Vec3(0, 0, -kG);
  particles::Particle p;
  particles::PairHistory history;

  Vec3 force(double dt) {
    contact::Contact c;
    c.normal = n;
    c.depth = depth0 - (p.position - x0).dot(n);
    c.touching = c.depth >= 0.0;
    Vec3 f = mass.mass * gravity;
    if (c.touching) {
      // B is fixed: m_eff = mA; A's point velocity is its centroid's (no rotation here).
      f += contactForce(c, p.velocity, mass.mass, dt, law, history).force;
    } else {
      resetShear(history);
    }
    return f;
  }
};

// Zhao Table 1: density 2500, kn 1.5e8 N/m, ks 1.2e8 N/m; a 1 m^3 block.
BlockOnPlane incline(double theta_deg, double mu) {
  const double theta = degToRad(theta_deg);
  BlockOnPlane b;
  b.n = Vec3(std::sin(theta), 0.0, std::cos(theta));
  b.mass = MassProperties{2500.0, Vec3::Constant(2500.0 / 6.0)};
  particles::ContactProperties props;
  props.kn = 1.5e8;
  props.ks = 1.2e8;
  props.friction_angle = radToDeg(std::atan(mu));
  b.law = lawCoefficients(props);
  // Start at the static overlap, so that the normal direction is in equilibrium from the outset.
  b.depth0 = b.mass.mass * kG * std::cos(theta) / props.kn;
  return b;
}

// Down-slope unit vector of the incline of normal n (in the x-z plane).
Vec3 downSlope(const Vec3& n) {
  return Vec3(n.z(), 0.0, -n.x());
}

// Displacement down the slope and velocity (at t - dt/2, the leapfrog's) of the block.
double slide(const BlockOnPlane& b) {
  return (b.p.position - b.x0).dot(downSlope(b.n));
}

// Zhao eq. 41 for u0 = 0: a block released on the incline, its friction fully mobilised when it
// is let go (the contact's shear already at the Coulomb cap, up the slope, as a block held in
// place and released would have it), slides with a = g (sin(theta) - mu cos(theta)) from t = 0:
// s = a t^2 / 2 within 1 %.
TEST(Coupled, ReleasedBlockSlidesDownTheIncline) {
  const double theta = degToRad(30.0);
  for (double mu : {0.2, 0.4}) {
    BlockOnPlane b = incline(30.0, mu);
    b.history.touching = 1;
    b.history.normal = b.n;
    b.history.shear_force = -mu * b.mass.mass * kG * std::cos(theta) * downSlope(b.n);
    const double a = kG * (std::sin(theta) - mu * std::cos(theta));
    const double dt = 1e-4;
    startLeapfrog(b.p, b.mass, b.force(dt), Vec3::Zero(), dt);
    double worst = 0.0;
    for (int n = 1; n <= 20000; ++n) {
      advanceFree(b.p, b.mass, b.force(dt), Vec3::Zero(), dt, 0.0);
      const double t = n * dt, expected = 0.5 * a * t * t;
      worst = std::max(worst, std::abs(slide(b) - expected) / expected);
    }
    std::printf("measured: released block, mu %.1f: max |s - a t^2/2| / s = %.2e over 2 s\n", mu,
                worst);
    EXPECT_LT(worst, 0.01) << "mu " << mu;
  }
}

// The same block put down with an unloaded shear spring first sticks: it swings on the spring ks
// (w_s = sqrt(ks / m)) with s = (g sin(theta) / w_s^2)(1 - cos(w_s t)) until ks s reaches the cap,
// then slips with the acceleration a of eq. 41 from the velocity it had. The law must follow this
// elastic-plastic solution exactly (to the leapfrog's error); it differs from the rigid eq. 41 by
// a velocity offset of order mu g cos(theta) / w_s, which vanishes as ks grows.
TEST(Coupled, BlockPutDownOnTheInclineSticksThenSlides) {
  const double theta = degToRad(30.0);
  for (double mu : {0.2, 0.4}) {
    BlockOnPlane b = incline(30.0, mu);
    const double m = b.mass.mass, ks = 1.2e8, ws = std::sqrt(ks / m);
    const double drive = kG * std::sin(theta);                  // m/s^2 down the slope
    const double cap = mu * m * kG * std::cos(theta);           // N
    const double tc = std::acos(1.0 - cap / (m * drive)) / ws;  // ks s(tc) = cap
    const double sc = cap / ks, vc = drive / ws * std::sin(ws * tc);
    const double a = drive - cap / m;
    auto exact = [&](double t) {
      return t <= tc ? drive / (ws * ws) * (1.0 - std::cos(ws * t))
                     : sc + vc * (t - tc) + 0.5 * a * (t - tc) * (t - tc);
    };
    const double dt = 1e-4;
    startLeapfrog(b.p, b.mass, b.force(dt), Vec3::Zero(), dt);
    double worst = 0.0, worst_rigid = 0.0;
    for (int n = 1; n <= 20000; ++n) {
      advanceFree(b.p, b.mass, b.force(dt), Vec3::Zero(), dt, 0.0);
      const double t = n * dt, s = slide(b);
      worst = std::max(worst, std::abs(s - exact(t)) / exact(2.0));
      if (t >= 0.5)
        worst_rigid = std::max(worst_rigid, std::abs(s - 0.5 * a * t * t) / (0.5 * a * t * t));
    }
    std::printf(
        "measured: block put down, mu %.1f: max |s - elastic-plastic| / s(2 s) = %.2e; "
        "vs rigid eq. 41 for t >= 0.5 s: %.2e (slip velocity offset %.4f m/s)\n",
        mu, worst, worst_rigid, vc - a * tc);
    // Leapfrog error of the stick swing (w_s dt = 0.022) and the slip onset resolved to one step.
    EXPECT_LT(worst, 1e-3) << "mu " << mu;
  }
}

// Zhao eq. 41-42 with u0 = 6 m/s up the slope (Table 1 materials): deceleration
// a1 = g (sin + mu cos) until t1 = u0 / a1, at s0 = u0 t1 / 2. Then the shear spring unloads from
// the cap: the block swings down on it, y = s0 - s = Y (1 - cos(w_s tau)),
// Y = (m g sin + cap) / ks, until the shear reaches the cap the other way (ks y = 2 cap; the swing
// always gets there since 2 Y ks > 2 cap), and slides on with a2 = g (sin - mu cos). For mu = 0.6
// > tan 30 deg, a2 < 0: the slide stops again after vc / |a2| and the block stays (its elastic
// ringing after that, below 2 cap / ks ~ 1e-4 s0, is left out). This elastic-plastic solution is
// asserted to 1e-3 of s0; the distance to the rigid eq. 41 is printed.
TEST(Coupled, BlockLaunchedUpTheInclineFollowsZhaoEq41) {
  const double theta = degToRad(30.0), u0 = 6.0;
  for (double mu : {0.2, 0.4, 0.6}) {
    BlockOnPlane b = incline(30.0, mu);
    const Vec3 up = -downSlope(b.n);
    b.p.velocity = u0 * up;
    const double m = b.mass.mass, ks = 1.2e8, ws = std::sqrt(ks / m);
    const double cap = mu * m * kG * std::cos(theta);
    const double a1 = kG * std::sin(theta) + cap / m, a2 = kG * std::sin(theta) - cap / m;
    const double t1 = u0 / a1, s0 = 0.5 * u0 * t1;
    const double big_y = (m * kG * std::sin(theta) + cap) / ks;
    const double yc = 2.0 * cap / ks;
    const double tau_c = std::acos(1.0 - yc / big_y) / ws;
    const double vc = big_y * ws * std::sin(ws * tau_c);
    auto s_exact = [&](double t) {  // up the slope
      if (t <= t1) return u0 * t - 0.5 * a1 * t * t;
      const double tau = t - t1;
      if (tau <= tau_c) return s0 - big_y * (1.0 - std::cos(ws * tau));
      double r = tau - tau_c;
      if (a2 < 0.0) r = std::min(r, vc / -a2);
      return s0 - yc - vc * r - 0.5 * a2 * r * r;
    };
    auto s_rigid = [&](double t) {  // Zhao eq. 41
      return t <= t1 ? u0 * t - 0.5 * a1 * t * t
                     : s0 - 0.5 * std::max(a2, 0.0) * (t - t1) * (t - t1);
    };
    const double dt = 1e-4;
    startLeapfrog(b.p, b.mass, b.force(dt), Vec3::Zero(), dt);
    double worst = 0.0, worst_rigid = 0.0;
    for (int n = 1; n <= 20000; ++n) {
      advanceFree(b.p, b.mass, b.force(dt), Vec3::Zero(), dt, 0.0);
      const double t = n * dt, s = -slide(b);
      worst = std::max(worst, std::abs(s - s_exact(t)) / s0);
      worst_rigid = std::max(worst_rigid, std::abs(s - s_rigid(t)) / s0);
    }
    std::printf(
        "measured: launched block, mu %.1f: max |s - elastic-plastic| / s0 = %.2e, "
        "max |s - eq. 41| / s0 = %.2e\n",
        mu, worst, worst_rigid);
    EXPECT_LT(worst, 1e-3) << "mu " << mu;
  }
}

// A block resting on a horizontal plane, pushed down and released: with the normal dashpot of
// ratio zeta the overlap oscillates about m g / kn at w_d = w sqrt(1 - zeta^2) and each period
// multiplies the amplitude by exp(-2 pi zeta / sqrt(1 - zeta^2)).
TEST(Coupled, ViscousNormalDampingGivesTheDampedOscillatorDecay) {
  const double m = 1000.0, kn = 1e7, zeta = 0.05;
  const double w = std::sqrt(kn / m);
  BlockOnPlane b;
  b.n = Vec3::UnitZ();
  b.mass = MassProperties{m, Vec3::Constant(m / 6.0)};
  particles::ContactProperties props;
  props.kn = kn;
  props.ks = kn;
  props.friction_angle = 30.0;
  props.normal_damping = zeta;
  b.law = lawCoefficients(props);
  const double rest = m * kG / kn;
  b.depth0 = 1.5 * rest;  // amplitude rest / 2: the contact stays closed
  const double dt = 2.0 * kPi / w / 1000.0;
  startLeapfrog(b.p, b.mass, b.force(dt), Vec3::Zero(), dt);
  std::vector<double> peaks, times;
  double before = 0.0, previous = 0.0;
  for (int n = 1; n <= 8000 && peaks.size() < 6; ++n) {
    advanceFree(b.p, b.mass, b.force(dt), Vec3::Zero(), dt, 0.0);
    const double excess = b.depth0 - b.p.position.z() - rest;  // overlap beyond the static one
    if (n > 2 && previous > before && previous >= excess && previous > 0.0) {
      peaks.push_back(previous);
      times.push_back((n - 1) * dt);
    }
    before = previous;
    previous = excess;
  }
  ASSERT_EQ(peaks.size(), 6u);
  const double decrement = 2.0 * kPi * zeta / std::sqrt(1.0 - zeta * zeta);
  const double period = 2.0 * kPi / (w * std::sqrt(1.0 - zeta * zeta));
  for (std::size_t i = 1; i < peaks.size(); ++i) {
    // Expected discrete error: O(zeta w dt + (w dt)^2) ~ 3e-4 relative on the decrement, plus the
    // peak times sampled to dt/2 (~5e-4); 0.5 % bounds both.
    EXPECT_NEAR(std::log(peaks[i - 1] / peaks[i]), decrement, 5e-3 * decrement) << i;
    EXPECT_NEAR(times[i] - times[i - 1], period, 1.01 * dt) << i;
  }
  std::printf("measured: log decrement %.6f (analytical %.6f)\n",
              std::log(peaks[0] / peaks[5]) / 5.0, decrement);
}

}  // namespace
}  // namespace polydem::dynamics
