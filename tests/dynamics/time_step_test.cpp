// The time-step rule: its formula, and that it is exactly the leapfrog's stability limit for two
// equal masses joined by a (damped) spring, the case the rule's factor sqrt(2) is built on.
#include "polydem/dynamics/time_step.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "polydem/core/error.h"
#include "polydem/dynamics/integrator.h"

namespace polydem::dynamics {
namespace {

TimeStepParticle particle(Uid uid, double m, const Vec3& inertia, double r, double k,
                          double zeta = 0.0) {
  TimeStepParticle p;
  p.uid = uid;
  p.mass = m;
  p.principal_inertia = inertia;
  p.circumradius = r;
  p.stiffness = k;
  p.damping_ratio = zeta;
  return p;
}

TEST(TimeStep, FormulaForTranslationAndRotation) {
  TimeStepRule rule;
  rule.coordination = 4.0;
  rule.safety = 0.5;
  // Unit cube of mass 2000 kg: I = m/6, R = sqrt(3)/2, so I / R^2 = 2m/9 < m: rotation limits.
  const double m = 2000.0, k = 1e10;
  const auto cube = particle(3, m, Vec3::Constant(m / 6.0), std::sqrt(3.0) / 2.0, k);
  const std::vector<TimeStepParticle> one{cube};
  const TimeStepSuggestion s = suggestTimeStep(one, rule);
  const double expected = std::sqrt(2.0) * std::sqrt((m / 6.0) / (4.0 * k * 0.75));
  EXPECT_NEAR(s.critical, expected, 1e-15 * expected);
  EXPECT_NEAR(s.dt, 0.5 * expected, 1e-15 * expected);
  EXPECT_TRUE(s.rotational);
  EXPECT_EQ(s.uid, 3u);
  // A particle whose contacts act at its centroid (R = 0): translation only.
  const std::vector<TimeStepParticle> point{particle(9, m, Vec3::Constant(1.0), 0.0, k, 0.2)};
  const TimeStepSuggestion t = suggestTimeStep(point, rule);
  const double damping = std::sqrt(1.0 + 0.04) - 0.2;
  EXPECT_NEAR(t.critical, std::sqrt(2.0) * damping * std::sqrt(m / (4.0 * k)), 1e-15 * t.critical);
  EXPECT_FALSE(t.rotational);
}

TEST(TimeStep, SmallestParticleSetsTheStepWhateverTheOrder) {
  std::vector<TimeStepParticle> ps;
  for (Uid uid = 1; uid <= 20; ++uid) {
    const double size = 0.5 + 0.1 * static_cast<double>((uid * 7) % 20);
    const double m = 2000.0 * size * size * size;
    ps.push_back(particle(uid, m, Vec3::Constant(m * size * size / 6.0), 0.87 * size, 1e9));
  }
  ps.push_back(particle(21, 1.0, Vec3::Ones(), 0.5, 0.0));  // no stiffness: no constraint
  const TimeStepSuggestion a = suggestTimeStep(ps);
  std::reverse(ps.begin(), ps.end());
  const TimeStepSuggestion b = suggestTimeStep(ps);
  EXPECT_EQ(a.dt, b.dt);
  EXPECT_EQ(a.uid, b.uid);
  EXPECT_EQ(a.uid, 20u);  // (20 * 7) % 20 == 0: the smallest block
  EXPECT_TRUE(std::isinf(suggestTimeStep({}).dt));
}

// Two equal free masses joined by a spring k with a dashpot of ratio zeta: the relative motion has
// w^2 = 2k/m, and the leapfrog (damping on the half-step velocity, as the contact law does) is
// stable up to dt = (2 / w)(sqrt(1 + zeta^2) - zeta). The rule's critical step, with a coordination
// of 1, is that limit exactly: 0.98 of it stays bounded, 1.02 of it blows up.
double growth(double zeta, double fraction_of_critical) {
  const double m = 3.0, k = 5e6;
  TimeStepRule rule;
  rule.coordination = 1.0;
  const std::vector<TimeStepParticle> both{particle(1, m, Vec3::Ones(), 0.0, k, zeta),
                                           particle(2, m, Vec3::Ones(), 0.0, k, zeta)};
  const double dt = fraction_of_critical * suggestTimeStep(both, rule).critical;
  const MassProperties mass{m, Vec3::Ones()};
  particles::Particle a, b;
  a.position = Vec3(0.0, 0, 0);
  b.position = Vec3(1.0 + 1e-4, 0, 0);  // spring of rest length 1, stretched
  const double c = 2.0 * zeta * std::sqrt(0.5 * m * k);
  double largest = 0.0;
  for (int n = 0; n < 4000; ++n) {
    const double stretch = b.position.x() - a.position.x() - 1.0;
    const double rate = b.velocity.x() - a.velocity.x();
    const double f = k * stretch + c * rate;  // pulls a towards b
    advanceFree(a, mass, Vec3(f, 0, 0), Vec3::Zero(), dt, 0.0);
    advanceFree(b, mass, Vec3(-f, 0, 0), Vec3::Zero(), dt, 0.0);
    largest = std::max(largest, std::abs(stretch));
    if (largest > 1e4 * 1e-4) break;  // blown up; stop before overflowing
  }
  return largest / 1e-4;
}

TEST(TimeStep, CriticalStepIsTheStabilityLimitOfTwoMasses) {
  for (double zeta : {0.0, 0.3}) {
    std::printf(
        "measured: zeta %.1f, largest stretch / initial: %.3g at 0.98 dt_crit, %.3g at 1.02\n",
        zeta, growth(zeta, 0.98), growth(zeta, 1.02));
    EXPECT_LT(growth(zeta, 0.98), 20.0) << "zeta " << zeta;
    EXPECT_GT(growth(zeta, 1.02), 1e3) << "zeta " << zeta;
  }
}

TEST(TimeStep, WarningOnlyWhenTheStepIsTooLarge) {
  const std::vector<TimeStepParticle> one{particle(42, 1.0, Vec3::Constant(0.1), 0.5, 1e6)};
  const TimeStepSuggestion s = suggestTimeStep(one);
  EXPECT_EQ(timeStepWarning(s.dt, s), "");
  EXPECT_EQ(timeStepWarning(0.5 * s.dt, s), "");
  const std::string w = timeStepWarning(2.0 * s.dt, s);
  EXPECT_NE(w.find("particle 42"), std::string::npos) << w;
  EXPECT_NE(w.find("rotation"), std::string::npos) << w;
}

TEST(TimeStep, StiffnessOfTheContactModels) {
  particles::ContactProperties p;
  p.kn = 2e9;
  p.ks = 1.6e9;
  p.penalty = 2e9;
  EXPECT_EQ(penaltyStiffness(p), 2e9);
  p.ks = 1e8;
  // 0.1 m cube: largest face 0.01 m^2, inradius 0.05 m: 2 * 2e9 * 0.01 / 0.05.
  EXPECT_DOUBLE_EQ(potentialStiffness(p, 0.01, 0.05), 8e8);
  p.ks = 1e10;
  EXPECT_EQ(potentialStiffness(p, 0.01, 0.05), 1e10);
  EXPECT_THROW(potentialStiffness(p, 0.0, 0.05), Error);
}

TEST(TimeStep, RejectsBadInput) {
  const std::vector<TimeStepParticle> massless{particle(1, 0.0, Vec3::Ones(), 1.0, 1.0)};
  EXPECT_THROW(suggestTimeStep(massless), Error);
  const std::vector<TimeStepParticle> ok{particle(1, 1.0, Vec3::Ones(), 1.0, 1.0)};
  TimeStepRule rule;
  rule.safety = 1.5;
  EXPECT_THROW(suggestTimeStep(ok, rule), Error);
}

}  // namespace
}  // namespace polydem::dynamics
