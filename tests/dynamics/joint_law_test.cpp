// The joint laws (dynamics/joint_law.h) against their definitions (docs/scene-format.md,
// "Joints"): the registry, strength reduction, coulomb-residual's breaking on slip and on tension
// and its handover to newcomer sub-contacts, and Barton-Bandis' scale correction, mobilization
// table, peak, 70 degree cap and the roughness vanishing at sigma >= JCS.
#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <string>
#include <vector>

#include "polydem/core/error.h"
#include "polydem/dynamics/joint_law.h"
#include "polydem/dynamics/joint_laws.h"
#include "polydem/dynamics/sub_contact_law.h"

namespace polydem::dynamics {
namespace {

using contact::ContactArea;
using contact::FaceContact;
using contact::SubContact;

constexpr double kDt = 1e-5, kMass = 100.0;
constexpr double kPi = 3.141592653589793;

double tanDeg(double deg) {
  return std::tan(deg * kPi / 180.0);
}

// A square face contact of area `area` centred on the origin, normal +z, corners with features
// `features` (four), gaps g0 + slope_y * y.
std::vector<SubContact> square(double g0, double slope_y = 0.0, double area = 1.0,
                               std::vector<std::uint64_t> features = {1, 2, 3, 4}) {
  std::vector<SubContact> subs;
  const double h = 0.5 * std::sqrt(area);
  std::size_t k = 0;
  for (double x : {-h, h}) {
    for (double y : {-h, h}) {
      subs.push_back({features[k++], Vec3(x, y, 0), Vec3::UnitZ(), g0 + slope_y * y, 0.25});
    }
  }
  return subs;
}

LawCoefficients pairLaw() {
  LawCoefficients k;
  k.kn = 1e8;
  k.ks = 5e7;
  k.tan_friction = tanDeg(30.0);
  return k;
}

PairKinematics moving(double vx) {
  PairKinematics kin;
  kin.xa = Vec3(0, 0, 0.5);
  kin.xb = Vec3(0, 0, -0.5);
  kin.va = Vec3(vx, 0, 0);
  return kin;
}

// One step of the pair: kept histories in, kept histories out.
struct Step {
  PairForce force;
  std::vector<particles::SubFeature> keys;
  std::vector<particles::SubHistory> entries;
};

Step step(const std::vector<SubContact>& subs, const Step* last, const LawCoefficients& k,
          double vx, double area = 1.0) {
  const FaceContact fc{ContactArea::kFace, area, subs};
  Step out;
  out.keys.resize(subs.size());
  out.entries.resize(subs.size());
  SubContactScratch scratch;
  std::span<const particles::SubFeature> old_keys;
  std::span<const particles::SubHistory> old;
  if (last) {
    old_keys = last->keys;
    old = last->entries;
  }
  out.force = subContactForces(fc, old_keys, old, moving(vx), kMass, kDt, k,
                               {out.keys, out.entries}, scratch);
  out.keys.resize(static_cast<std::size_t>(out.force.kept));
  out.entries.resize(static_cast<std::size_t>(out.force.kept));
  return out;
}

TEST(JointLaws, RegistryDeclaresEveryLaw) {
  std::set<std::string> names;
  for (const JointLawInfo& law : jointLaws()) {
    EXPECT_TRUE(names.insert(law.name).second) << law.name;
    EXPECT_EQ(findJointLaw(law.name), &law);
    EXPECT_EQ(&jointLaw(law.id), &law);
    EXPECT_LE(law.history_columns.size(), particles::kMaxLawHistory);
    EXPECT_EQ(parameterIndex(law, "jkn"), 0) << law.name;
    EXPECT_EQ(parameterIndex(law, "jks"), 1) << law.name;
  }
  EXPECT_EQ(names, (std::set<std::string>{"coulomb", "coulomb-residual", "barton-bandis"}));
  EXPECT_EQ(findJointLaw("mohr"), nullptr);
  EXPECT_EQ(jointLaw(JointLaw::kCoulombResidual).history_columns.size(), 1u);
  EXPECT_EQ(jointLaw(JointLaw::kBartonBandis).history_columns.size(), 2u);
  EXPECT_EQ(jointLaw(JointLaw::kCoulomb).history_columns.size(), 0u);
}

// Strength reduction (polydem fos): tan(phi) / F, c / F, sigma_t / F for the Coulomb laws (the
// residual angle too), tau / F for Barton-Bandis with its parameters and stiffness unchanged.
TEST(JointLaws, StrengthReductionByF) {
  const double f = 1.7;
  const JointParameters coulomb{JointLaw::kCoulomb, {1e9, 5e8, 35.0, 4e4, 1e5}};
  const JointParameters c = reduceJointStrength(coulomb, f);
  EXPECT_EQ(c.values[0], 1e9);
  EXPECT_EQ(c.values[1], 5e8);
  EXPECT_NEAR(tanDeg(c.values[2]), tanDeg(35.0) / f, 1e-14);
  EXPECT_NEAR(c.values[3], 4e4 / f, 1e-9);
  EXPECT_NEAR(c.values[4], 1e5 / f, 1e-9);
  EXPECT_EQ(c.strength_divisor, 1.0);
  const JointParameters residual{JointLaw::kCoulombResidual, {1e9, 5e8, 35.0, 4e4, 1e5, 25.0}};
  const JointParameters r = reduceJointStrength(residual, f);
  EXPECT_NEAR(tanDeg(r.values[5]), tanDeg(25.0) / f, 1e-14);
  const JointParameters bb{JointLaw::kBartonBandis, {1e9, 5e8, 10.0, 1e8, 30.0, 0.1, 0.0, 0.0}};
  const JointParameters b = reduceJointStrength(bb, f);
  EXPECT_EQ(b.values, bb.values);
  EXPECT_EQ(b.strength_divisor, f);
  EXPECT_EQ(reduceJointStrength(b, 2.0).strength_divisor, 2.0 * f);
  EXPECT_THROW(reduceJointStrength(bb, 0.0), Error);
  // The reduced Barton-Bandis joint's sliding shear is tau / F.
  const auto slide = [&](const JointParameters& j) {
    const LawCoefficients k = jointCoefficients(j, pairLaw());
    const Step first = step(square(1e-4), nullptr, k, 1.0);  // mobilizes along the way
    Step s = step(square(1e-4), &first, k, 100.0);
    return s.force.shear;
  };
  EXPECT_NEAR(slide(b), slide(bb) / f, 1e-9 * slide(bb));
}

TEST(JointLaws, CoefficientsRefuseValuesOutsideTheirRange) {
  EXPECT_THROW(jointCoefficients({JointLaw::kCoulomb, {0.0, 5e8, 30.0, 0.0, 0.0}}, pairLaw()),
               Error);
  EXPECT_THROW(jointCoefficients({JointLaw::kCoulomb, {1e9, 5e8, 90.0, 0.0, 0.0}}, pairLaw()),
               Error);
  EXPECT_THROW(
      jointCoefficients({JointLaw::kBartonBandis, {1e9, 5e8, 21.0, 1e8, 30, 0.1, 0, 0}}, pairLaw()),
      Error);
  EXPECT_THROW(jointCoefficients({JointLaw::kCoulomb, {1e9, 5e8, 30.0}}, pairLaw()), Error);
}

// --- coulomb-residual

constexpr double kJkn = 1e9, kJks = 5e8, kPhi = 30.0, kPhiR = 20.0, kC = 2e4;

LawCoefficients residualLaw(double sigma_t = 0.0) {
  return jointCoefficients({JointLaw::kCoulombResidual, {kJkn, kJks, kPhi, kC, sigma_t, kPhiR}},
                           pairLaw());
}

// An intact sub-contact is the coulomb law's, bit for bit.
TEST(CoulombResidual, IntactIsCoulomb) {
  const LawCoefficients coulomb =
      jointCoefficients({JointLaw::kCoulomb, {kJkn, kJks, kPhi, kC, 0.0}}, pairLaw());
  const Step a = step(square(1e-4, 1e-5), nullptr, residualLaw(), 1e-3);
  const Step b = step(square(1e-4, 1e-5), nullptr, coulomb, 1e-3);
  EXPECT_FALSE(a.force.sliding);
  EXPECT_EQ(a.force.force, b.force.force);
  EXPECT_EQ(a.force.torque_a, b.force.torque_a);
  for (const auto& e : a.entries) EXPECT_EQ(e.law[0], 0.0);
}

// Slip breaks it: the step that slips holds the peak c A + N tan(phi); from the next step on,
// N tan(phi_r), also when it has stopped sliding (a slow step whose shear is below the peak
// but above the residual is held at the residual).
TEST(CoulombResidual, BreaksOnSlipAndStaysBroken) {
  const LawCoefficients k = residualLaw();
  const double n = kJkn * 1e-4;  // A = 1
  Step s = step(square(1e-4), nullptr, k, 100.0);
  EXPECT_TRUE(s.force.sliding);
  EXPECT_NEAR(s.force.shear, kC + n * tanDeg(kPhi), 1e-9 * s.force.shear);
  ASSERT_EQ(s.entries.size(), 4u);
  for (const auto& e : s.entries) EXPECT_EQ(e.law[0], 1.0);
  Step t = step(square(1e-4), &s, k, 100.0);
  EXPECT_NEAR(t.force.shear, n * tanDeg(kPhiR), 1e-9 * n);
  // At rest, the shear carried over (the residual) stays; a small push cannot exceed it.
  Step u = step(square(1e-4), &t, k, 0.0);
  EXPECT_NEAR(u.force.shear, n * tanDeg(kPhiR), 1e-9 * n);
  Step v = step(square(1e-4), &u, k, 1e-3);
  EXPECT_NEAR(v.force.shear, n * tanDeg(kPhiR), 1e-9 * n);
  for (const auto& e : v.entries) EXPECT_EQ(e.law[0], 1.0);
}

// Opening beyond the tensile strength breaks a corner: it is kept, broken, while the pair
// touches, and carries no tension and no cohesion when it closes again.
TEST(CoulombResidual, BreaksOnTensionAndStaysBroken) {
  const double sigma_t = 1e5;  // gaps down to -1e-4 m pull
  const LawCoefficients k = residualLaw(sigma_t);
  const Step closed = step(square(1e-4), nullptr, k, 0.0);
  for (const auto& e : closed.entries) EXPECT_EQ(e.law[0], 0.0);
  // Gaps -1.1e-4 on the -y side (beyond -sigma_t / jkn), 1.9e-4 on +y.
  const Step pulled = step(square(0.4e-4, 3e-4), &closed, k, 0.0);
  EXPECT_EQ(pulled.force.loaded, 2);
  ASSERT_EQ(pulled.force.kept, 4);
  EXPECT_EQ(pulled.entries[0].law[0], 1.0);  // (-0.5, -0.5)
  EXPECT_EQ(pulled.entries[1].law[0], 0.0);  // (-0.5, +0.5)
  EXPECT_EQ(pulled.entries[2].law[0], 1.0);
  EXPECT_EQ(pulled.entries[3].law[0], 0.0);
  // Pulled less far (-0.9e-4, within the tensile strength of an intact corner, which would pull:
  // SubContactLaw.JointTensileStrengthLetsOpenCornersPull): the broken corners carry nothing.
  const Step again = step(square(0.5e-4, 2.8e-4), &pulled, k, 0.0);
  EXPECT_EQ(again.force.loaded, 2);
  EXPECT_NEAR(again.force.normal, 0.25 * kJkn * 2 * 1.9e-4, 1e-6);
  // Closed again and slid: the broken corners hold N_i tan(phi_r), the intact ones c A / 4 +
  // N_i tan(phi) at the step they slip.
  const Step slid = step(square(1e-4), &again, k, 100.0);
  const double ni = 0.25 * kJkn * 1e-4;
  EXPECT_NEAR(slid.force.shear, 2 * ni * tanDeg(kPhiR) + 2 * (ni * tanDeg(kPhi) + 0.25 * kC),
              1e-9 * slid.force.shear);
}

// A sub-contact that appears takes the broken flag of the vanished ones whose shear it takes.
TEST(CoulombResidual, NewcomersInheritBrokenFromTheVanished) {
  const LawCoefficients k = residualLaw();
  Step last = step(square(1e-4), nullptr, k, 0.0);
  for (const bool broken : {false, true}) {
    last.entries[0].law[0] = broken ? 1.0 : 0.0;  // feature 1 vanishes below
    last.entries[1].law[0] = 0.0;
    const Step next = step(square(1e-4, 0.0, 1.0, {2, 3, 4, 5}), &last, k, 0.0);
    ASSERT_EQ(next.entries.size(), 4u);
    EXPECT_EQ(next.keys[3].feature, 5u);
    EXPECT_EQ(next.entries[3].law[0], broken ? 1.0 : 0.0);
    EXPECT_EQ(next.entries[0].law[0], 0.0) << "feature 2 keeps its own";
  }
  // A broken corner that stays does not pass its flag on.
  last.entries[0].law[0] = 0.0;
  last.entries[1].law[0] = 1.0;
  const Step next = step(square(1e-4, 0.0, 1.0, {2, 3, 4, 5}), &last, k, 0.0);
  EXPECT_EQ(next.entries[0].law[0], 1.0);
  EXPECT_EQ(next.entries[3].law[0], 0.0);
}

// --- barton-bandis

TEST(BartonBandis, ScaleCorrection) {
  const double jrc0 = 10.0, jcs0 = 1e8, l0 = 0.1;
  const BartonBandisScale same = bartonBandisScale(jrc0, jcs0, l0, l0);
  EXPECT_EQ(same.jrc, jrc0);
  EXPECT_EQ(same.jcs, jcs0);
  for (const double ln : {1.0, 5.0}) {
    const BartonBandisScale s = bartonBandisScale(jrc0, jcs0, l0, ln);
    EXPECT_NEAR(s.jrc, jrc0 * std::pow(ln / l0, -0.02 * jrc0), 1e-12);
    EXPECT_NEAR(s.jcs, jcs0 * std::pow(ln / l0, -0.03 * jrc0), 1e-4);
    EXPECT_NEAR(s.delta_p, ln / 500.0 * std::pow(s.jrc / ln, 0.33), 1e-15);
    EXPECT_LT(s.jrc, jrc0);
    EXPECT_LT(s.jcs, jcs0);
  }
  // At 1 m: JRC_n = 10 * 10^-0.2 = 6.3096, JCS_n = 1e8 * 10^-0.3 = 5.0119e7 Pa,
  // delta_p = (1 / 500) 6.3096^0.33 = 3.6731e-3 m.
  const BartonBandisScale m = bartonBandisScale(jrc0, jcs0, l0, 1.0);
  EXPECT_NEAR(m.jrc, 6.3096, 1e-4);
  EXPECT_NEAR(m.jcs, 5.0119e7, 1e3);
  EXPECT_NEAR(m.delta_p, 3.6731e-3, 1e-7);
}

// The table of Barton (1982) at its points and between them.
TEST(BartonBandis, MobilizationTable) {
  const double i = 12.0, phi_r = 30.0;
  EXPECT_DOUBLE_EQ(bartonBandisMobilization(0.0, i, phi_r), -phi_r / i);
  EXPECT_DOUBLE_EQ(bartonBandisMobilization(0.0, 0.0, phi_r), 0.0);
  EXPECT_DOUBLE_EQ(bartonBandisMobilization(0.15, i, phi_r), -0.5 * phi_r / i);
  const std::vector<std::pair<double, double>> points{{0.3, 0.0},   {0.6, 0.75}, {1.0, 1.0},
                                                      {2.0, 0.85},  {4.0, 0.70}, {10.0, 0.5},
                                                      {100.0, 0.0}, {500.0, 0.0}};
  for (const auto& [r, m] : points) EXPECT_NEAR(bartonBandisMobilization(r, i, phi_r), m, 1e-15);
  EXPECT_NEAR(bartonBandisMobilization(0.8, i, phi_r), 0.875, 1e-15);
  EXPECT_NEAR(bartonBandisMobilization(3.0, i, phi_r), 0.775, 1e-15);
  EXPECT_NEAR(bartonBandisMobilization(55.0, i, phi_r), 0.25, 1e-15);
}

// tau(sigma, delta): 0 at delta = 0, phi_r at 0.3 delta_p, the peak sigma tan(phi_r + i) at
// delta_p (the largest along the way), the residual sigma tan(phi_r) from 100 delta_p on.
TEST(BartonBandis, PeakAtDeltaPThenResidual) {
  const BartonBandisScale s = bartonBandisScale(10.0, 1e8, 0.1, 1.0);
  const double phi_r = 28.0, sigma = 1e6;
  const double i = s.jrc * std::log10(s.jcs / sigma);
  const double peak = sigma * tanDeg(phi_r + i);
  EXPECT_NEAR(bartonBandisStrength(s, phi_r, sigma, 0.0), 0.0, 1e-9 * peak);
  EXPECT_NEAR(bartonBandisStrength(s, phi_r, sigma, 0.3 * s.delta_p), sigma * tanDeg(phi_r),
              1e-9 * peak);
  EXPECT_NEAR(bartonBandisStrength(s, phi_r, sigma, s.delta_p), peak, 1e-9 * peak);
  for (const double r : {0.5, 0.9, 0.99, 1.01, 1.5, 3.0, 20.0}) {
    EXPECT_LT(bartonBandisStrength(s, phi_r, sigma, r * s.delta_p), peak) << r;
  }
  EXPECT_NEAR(bartonBandisStrength(s, phi_r, sigma, 2.0 * s.delta_p),
              sigma * tanDeg(phi_r + 0.85 * i), 1e-9 * peak);
  for (const double r : {100.0, 1e4}) {
    EXPECT_NEAR(bartonBandisStrength(s, phi_r, sigma, r * s.delta_p), sigma * tanDeg(phi_r),
                1e-9 * peak);
  }
  // The peak grows less than in proportion to sigma: i falls as log10(JCS / sigma).
  const double peak2 = bartonBandisStrength(s, phi_r, 2 * sigma, s.delta_p);
  EXPECT_NEAR(peak2, 2 * sigma * tanDeg(phi_r + s.jrc * std::log10(s.jcs / (2 * sigma))),
              1e-9 * peak2);
  EXPECT_LT(peak2, 2 * peak);
}

TEST(BartonBandis, AngleCappedAt70Degrees) {
  const BartonBandisScale s = bartonBandisScale(20.0, 1e8, 0.1, 0.1);
  const double phi_r = 30.0, sigma = 1e3;  // i = 20 log10(1e5) = 100 degrees
  EXPECT_NEAR(bartonBandisStrength(s, phi_r, sigma, s.delta_p), sigma * tanDeg(70.0), 1e-9 * sigma);
  EXPECT_EQ(bartonBandisAngle(phi_r, 1.0, 100.0), 70.0);
  EXPECT_EQ(bartonBandisAngle(phi_r, 0.5, 10.0), 35.0);
}

// sigma >= JCS_n: no roughness, the residual angle at any displacement (also at 0); sigma <= 0:
// no strength.
TEST(BartonBandis, NoRoughnessAtOrAboveJcs) {
  const BartonBandisScale s = bartonBandisScale(10.0, 1e8, 0.1, 0.1);
  const double phi_r = 25.0;
  for (const double sigma : {1e8, 2e8}) {
    EXPECT_EQ(bartonBandisRoughness(s, sigma), 0.0);
    for (const double delta : {0.0, 0.5 * s.delta_p, s.delta_p, 50 * s.delta_p}) {
      EXPECT_NEAR(bartonBandisStrength(s, phi_r, sigma, delta), sigma * tanDeg(phi_r),
                  1e-9 * sigma);
    }
  }
  EXPECT_EQ(bartonBandisStrength(s, phi_r, 0.0, s.delta_p), 0.0);
  EXPECT_EQ(bartonBandisStrength(s, phi_r, -1e5, s.delta_p), 0.0);
  EXPECT_GT(bartonBandisRoughness(s, 0.99e8), 0.0);
}

// In the sub-contact loop: each sub-contact's delta is the sum of |v_t| dt, sigma = jkn g, and a
// sliding sub-contact holds w A tau(sigma, delta) with L_n = sqrt(A) by default.
TEST(BartonBandis, SubContactsAccumulateDisplacementAndHoldTau) {
  const double jkn = 1e10, jks = 1e10, gap = 1e-4, area = 4.0, phi_r = 30.0;
  const LawCoefficients k = jointCoefficients(
      {JointLaw::kBartonBandis, {jkn, jks, 10.0, 1e8, phi_r, 0.1, 0.0, 0.0}}, pairLaw());
  const BartonBandisScale s = bartonBandisScale(10.0, 1e8, 0.1, std::sqrt(area));
  const double sigma = jkn * gap, v = 5.0;
  Step last = step(square(gap, 0.0, area), nullptr, k, v, area);
  double delta = v * kDt;
  for (int n = 0; n < 400; ++n) {
    last = step(square(gap, 0.0, area), &last, k, v, area);
    delta += v * kDt;
    for (const auto& e : last.entries) EXPECT_NEAR(e.law[0], delta, 1e-12 * delta);
    ASSERT_TRUE(last.force.sliding) << n;
    EXPECT_NEAR(last.force.shear, area * bartonBandisStrength(s, phi_r, sigma, delta),
                1e-9 * last.force.shear)
        << n;
  }
  EXPECT_GT(delta, s.delta_p) << "the run passes the peak";
  // With field_length: the scale of that length, whatever the area.
  const LawCoefficients fixed = jointCoefficients(
      {JointLaw::kBartonBandis, {jkn, jks, 10.0, 1e8, phi_r, 0.1, 5.0, 0.0}}, pairLaw());
  const BartonBandisScale s5 = bartonBandisScale(10.0, 1e8, 0.1, 5.0);
  Step a = step(square(gap, 0.0, area), nullptr, fixed, 1.0, area);
  a.entries[0].law[0] = a.entries[1].law[0] = a.entries[2].law[0] = a.entries[3].law[0] =
      s5.delta_p - 100.0 * kDt;
  const Step b = step(square(gap, 0.0, area), &a, fixed, 100.0, area);
  EXPECT_NEAR(b.force.shear, area * sigma * tanDeg(phi_r + s5.jrc * std::log10(s5.jcs / sigma)),
              1e-9 * b.force.shear);
}

// Dilation (optional): while slipping, the opening grows by tan(0.5 max(m, 0) i) |v_t| dt and
// pushes the surfaces apart (a larger normal force at the same gap); none before 0.3 delta_p,
// where m < 0; off by default.
TEST(BartonBandis, DilationWhileSlipping) {
  const double jkn = 1e10, gap = 1e-4, phi_r = 30.0;
  const JointParameters off{JointLaw::kBartonBandis, {jkn, 1e10, 10.0, 1e8, phi_r, 0.1, 0.0, 0.0}};
  JointParameters on = off;
  on.values[7] = 1.0;
  const BartonBandisScale s = bartonBandisScale(10.0, 1e8, 0.1, 1.0);
  const auto run = [&](const JointParameters& j) {
    const LawCoefficients k = jointCoefficients(j, pairLaw());
    Step last = step(square(gap), nullptr, k, 5.0);
    for (int n = 0; n < 2000; ++n) last = step(square(gap), &last, k, 5.0);
    return last;
  };
  const Step plain = run(off), dilated = run(on);
  // Before 0.3 delta_p nothing opens.
  const LawCoefficients k_on = jointCoefficients(on, pairLaw());
  Step early = step(square(gap), nullptr, k_on, 5.0);
  for (int n = 0; n < 10; ++n) early = step(square(gap), &early, k_on, 5.0);
  ASSERT_LT(early.entries[0].law[0], 0.3 * s.delta_p);
  EXPECT_TRUE(early.force.sliding);
  for (const auto& e : early.entries) EXPECT_EQ(e.law[1], 0.0);
  for (const auto& e : plain.entries) EXPECT_EQ(e.law[1], 0.0);
  const double delta = plain.entries[0].law[0];
  EXPECT_GT(delta, 2 * s.delta_p);
  // Past 0.3 delta_p the mobilized dilation is positive: an opening, at most tan(0.5 i) delta.
  const double opening = dilated.entries[0].law[1];
  const double i = s.jrc * std::log10(s.jcs / (jkn * gap));
  EXPECT_GT(opening, 0.0);
  EXPECT_LT(opening, tanDeg(0.5 * i) * delta);
  // At rest (no slip, no more opening) the normal force is jkn A (g + opening).
  const Step rest = step(square(gap), &dilated, k_on, 0.0);
  EXPECT_EQ(rest.entries[0].law[1], opening);
  EXPECT_NEAR(rest.force.normal, jkn * (gap + opening), 1e-9 * rest.force.normal);
}

}  // namespace
}  // namespace polydem::dynamics
