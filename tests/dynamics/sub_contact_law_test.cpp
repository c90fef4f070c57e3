// The contact law of a pair split into sub-contacts (dynamics/sub_contact_law.h): resultant,
// restoring moment, damping, Coulomb limit per corner, twist, the spin of the shear springs, and
// the hand-over of shear when the corners change, against hand-computed answers for a square
// face contact.
#include "polydem/dynamics/sub_contact_law.h"

#include "polydem/dynamics/joint_law.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace polydem::dynamics {
namespace {

using contact::ContactArea;
using contact::FaceContact;
using contact::SubContact;

constexpr double kKn = 1e8, kKs = 5e7, kDt = 1e-5, kMass = 100.0;

// A 1 x 1 square face contact centred on the origin, normal +z, corner gaps g0 + slope_y * y.
std::vector<SubContact> square(double g0, double slope_y = 0.0) {
  std::vector<SubContact> subs;
  std::uint64_t feature = 1;
  for (double x : {-0.5, 0.5}) {
    for (double y : {-0.5, 0.5}) {
      subs.push_back({feature++, Vec3(x, y, 0), Vec3::UnitZ(), g0 + slope_y * y, 0.25});
    }
  }
  return subs;
}

FaceContact face(const std::vector<SubContact>& subs, double area = 1.0) {
  return {ContactArea::kFace, area, subs};
}

LawCoefficients law(double friction_deg = 30.0) {
  LawCoefficients k;
  k.kn = kKn;
  k.ks = kKs;
  k.tan_friction = std::tan(friction_deg * M_PI / 180.0);
  return k;
}

// A above B, centroids 0.5 above and below the contact plane.
PairKinematics still() {
  PairKinematics kin;
  kin.xa = Vec3(0, 0, 0.5);
  kin.xb = Vec3(0, 0, -0.5);
  return kin;
}

TEST(SubContactLaw, UniformGapGivesThePairsSpringAtTheCentre) {
  const auto subs = square(1e-4);
  std::vector<particles::SubEntry> kept;
  const auto f = subContactForces(face(subs), {}, {}, still(), kMass, kDt, law(), kept);
  EXPECT_NEAR(f.force.z(), kKn * 1e-4, 1e-9);
  EXPECT_NEAR(f.force.head<2>().norm(), 0.0, 1e-12);
  EXPECT_NEAR(f.torque_a.norm(), 0.0, 1e-9) << "the resultant acts below A's centroid";
  EXPECT_NEAR(f.normal, kKn * 1e-4, 1e-9);
  EXPECT_EQ(f.loaded, 4);
  EXPECT_EQ(kept.size(), 4u);
  EXPECT_NEAR(f.centre.norm(), 0.0, 1e-15);
}

// Tilted about x, deeper on the +y side: a moment about -x turns A back (the single-point model
// has none while the whole face overlaps). M = -kn sum w y^2 slope = -kn slope / 4.
TEST(SubContactLaw, TiltGivesARestoringMoment) {
  const double slope = 1e-5;
  std::vector<particles::SubEntry> kept;
  const auto f =
      subContactForces(face(square(1e-4, slope)), {}, {}, still(), kMass, kDt, law(), kept);
  EXPECT_NEAR(f.force.z(), kKn * 1e-4, 1e-9);
  EXPECT_NEAR(f.torque_a.x(), kKn * 0.25 * slope, 1e-9);
  // A's corners on the +y side are pushed up harder: the moment about +x lifts +y, i.e. turns the
  // deeper side out of B.
  EXPECT_GT(f.torque_a.x(), 0.0);
}

TEST(SubContactLaw, OpenCornersCarryNothingAndAreReleased) {
  auto subs = square(1e-4, 4e-4);  // gaps -1e-4 on the -y side, 3e-4 on +y
  std::vector<particles::SubEntry> kept;
  const auto f = subContactForces(face(subs), {}, {}, still(), kMass, kDt, law(), kept);
  EXPECT_EQ(f.loaded, 2);
  EXPECT_EQ(kept.size(), 2u);
  EXPECT_NEAR(f.force.z(), kKn * 0.25 * 2 * 3e-4, 1e-9);
  EXPECT_NEAR(f.centre.y(), 0.5, 1e-15);
}

// Viscous damping: a uniform approach meets the pair's dashpot 2 zeta sqrt(m kn), shared by weight.
TEST(SubContactLaw, DampingOfAUniformApproachIsThePairs) {
  auto k = law();
  k.damping_ratio = 0.1;
  PairKinematics kin = still();
  kin.va = Vec3(0, 0, -0.01);  // A moves into B
  std::vector<particles::SubEntry> kept;
  const auto f = subContactForces(face(square(1e-4)), {}, {}, kin, kMass, kDt, k, kept);
  EXPECT_NEAR(f.force.z(), kKn * 1e-4 + 2 * 0.1 * std::sqrt(kMass * kKn) * 0.01, 1e-8);
}

// Sliding fast: every corner at its own Coulomb limit, the total shear mu times the normal force.
TEST(SubContactLaw, SlidingPairReachesMuTimesTheNormalForce) {
  PairKinematics kin = still();
  kin.va = Vec3(100, 0, 0);  // ks dt v per corner far above the cap
  std::vector<particles::SubEntry> kept;
  const auto f = subContactForces(face(square(1e-4, 2e-5)), {}, {}, kin, kMass, kDt, law(), kept);
  EXPECT_TRUE(f.sliding);
  EXPECT_NEAR(f.shear, std::tan(M_PI / 6) * f.normal, 1e-9 * f.normal);
  EXPECT_LT(f.force.x(), 0.0) << "opposes A's motion";
}

// A twisting against B about the normal: the corner springs load around the square and resist
// the twist; after one step the moment is -ks dt w sum w_i r_i^2 = -ks dt w / 2.
TEST(SubContactLaw, TwistIsResisted) {
  PairKinematics kin = still();
  const double w = 0.2;
  kin.wa = Vec3(0, 0, w);
  std::vector<particles::SubEntry> kept;
  const auto f = subContactForces(face(square(1e-4)), {}, {}, kin, kMass, kDt, law(), kept);
  EXPECT_NEAR(f.torque_a.z(), -kKs * kDt * w * 0.5, 1e-12);
  EXPECT_NEAR(f.force.head<2>().norm(), 0.0, 1e-12) << "a pure twist has no net shear";
}

// Both bodies turning together about the normal: no relative motion, so the stored shear turns
// with them, magnitude kept (the Cayley rotation is exact).
TEST(SubContactLaw, ShearTurnsWithTheSpinOfThePair) {
  const auto subs = square(1e-4);
  std::vector<particles::SubFeature> keys;
  std::vector<particles::SubHistory> old;
  for (const auto& s : subs) {
    keys.push_back({s.feature});
    old.push_back({Vec3(100, 0, 0), Vec3::UnitZ()});
  }
  PairKinematics kin = still();
  const double omega = 3.0;
  kin.wa = kin.wb = Vec3(0, 0, omega);
  // Material velocities of the rigid rotation at the corners, the same on A and B.
  std::vector<particles::SubEntry> kept;
  subContactForces(face(subs), keys, old, kin, kMass, kDt, law(), kept);
  ASSERT_EQ(kept.size(), 4u);
  const double angle = 2 * std::atan(0.5 * kDt * omega);
  for (const auto& k : kept) {
    EXPECT_NEAR(k.history.shear_force.norm(), 100.0, 1e-10);
    EXPECT_NEAR(k.history.shear_force.x(), 100 * std::cos(angle), 1e-10);
    EXPECT_NEAR(k.history.shear_force.y(), 100 * std::sin(angle), 1e-10);
  }
}

TEST(SubContactLaw, SpinShearIsARotation) {
  const Vec3 n = Vec3(1, 2, 2).normalized();
  const Vec3 s = n.cross(Vec3(0.3, -1, 0.2)) * 7.0;
  for (double t : {1e-8, 1e-3, 0.4}) {
    const Vec3 r = spinShear(s, n, t);
    EXPECT_NEAR(r.norm(), s.norm(), 1e-14 * s.norm());
    EXPECT_NEAR(r.dot(n), 0.0, 1e-13 * s.norm());
    EXPECT_NEAR(std::atan2(n.dot(s.cross(r)), s.dot(r)), 2 * std::atan(t), 1e-12);
  }
}

// The corners change (one vertex of A crossed an edge of B): the shear the vanished corner held
// goes to the new corners in proportion to their weights, so the pair's stored shear is kept.
TEST(SubContactLaw, ShearOfVanishedCornersGoesToNewOnes) {
  auto subs = square(1e-4);
  std::vector<particles::SubFeature> keys;
  std::vector<particles::SubHistory> old;
  for (const auto& s : subs) {
    keys.push_back({s.feature});
    old.push_back({Vec3(10, 0, 0), Vec3::UnitZ()});
  }
  keys.push_back({99});  // a corner that is gone now
  old.push_back({Vec3(0, 8, 0), Vec3::UnitZ()});
  subs.push_back({100, Vec3(0.5, 0.0, 0), Vec3::UnitZ(), 1e-4, 0.1});  // two new corners
  subs.push_back({101, Vec3(0.5, 0.2, 0), Vec3::UnitZ(), 1e-4, 0.3});
  for (int i = 0; i < 4; ++i) subs[i].weight = 0.15;
  std::vector<particles::SubEntry> kept;
  subContactForces(face(subs), keys, old, still(), kMass, kDt, law(), kept);
  ASSERT_EQ(kept.size(), 6u);
  Vec3 total = Vec3::Zero();
  for (const auto& k : kept) total += k.history.shear_force;
  EXPECT_NEAR((total - Vec3(40, 8, 0)).norm(), 0.0, 1e-12);
  EXPECT_NEAR(kept[4].history.shear_force.y(), 2.0, 1e-12);  // 0.1 / 0.4 of 8
  EXPECT_NEAR(kept[5].history.shear_force.y(), 6.0, 1e-12);
}

// PairLaw keeps one working space for every pair and writes the kept sub-contacts straight into
// the next step's history table: what a larger pair left in either must not reach the next pair.
// The same pair (corners with and without history, an open one, a vanished one) after a
// six-corner pair with other histories gives the bits of a fresh working space and table.
TEST(SubContactLaw, ReusedWorkingSpaceGivesTheSameBits) {
  auto subs = square(1e-4, 3e-4);  // the corners at y = -0.5 are open
  std::vector<particles::SubFeature> keys;
  std::vector<particles::SubHistory> old;
  keys.push_back({0});  // gone now
  old.push_back({Vec3(0, 4, 0), Vec3::UnitZ()});
  keys.push_back({subs[3].feature});
  old.push_back({Vec3(3, -1, 0), Vec3(0.01, 0, 1).normalized()});
  PairKinematics kin = still();
  kin.va = Vec3(0.01, -0.02, -0.003);
  kin.wa = Vec3(0.1, 0.2, 0.3);

  // As PairLaw: the pair's entry, then its sub-contacts written in place.
  auto step = [&](const std::vector<SubContact>& s, std::span<const particles::SubFeature> k,
                  std::span<const particles::SubHistory> h, const particles::PairKey& pair,
                  SubContactScratch& scratch, particles::ContactHistory& next) {
    next.appendSorted(pair, {});
    const auto f =
        subContactForces(face(s), k, h, kin, kMass, kDt, law(), next.openSubs(s.size()), scratch);
    next.closeSubs(static_cast<std::size_t>(f.loaded));
    return f;
  };
  SubContactScratch fresh, reused;
  particles::ContactHistory table_fresh, table_reused;
  const auto expected = step(subs, keys, old, {1, 2}, fresh, table_fresh);

  auto big = square(2e-4);  // a larger pair first, every corner carried over
  big.push_back({7, Vec3(0.6, 0, 0), Vec3::UnitZ(), 2e-4, 0.0});
  big.push_back({8, Vec3(0.6, 0.1, 0), Vec3::UnitZ(), 2e-4, 0.0});
  std::vector<particles::SubFeature> big_keys;
  std::vector<particles::SubHistory> big_old;
  for (const auto& s : big) {
    big_keys.push_back({s.feature});
    big_old.push_back({Vec3(50, 50, 0), Vec3::UnitZ()});
  }
  step(big, big_keys, big_old, {0, 1}, reused, table_reused);
  ASSERT_EQ(table_reused.subFeatures().size(), 6u);
  const auto f = step(subs, keys, old, {1, 2}, reused, table_reused);

  EXPECT_EQ(f.force, expected.force);
  EXPECT_EQ(f.torque_a, expected.torque_a);
  EXPECT_EQ(f.torque_b, expected.torque_b);
  EXPECT_EQ(f.energy, expected.energy);
  const auto kept_fresh = table_fresh.subEntries();
  const auto kept_reused = table_reused.subEntries().subspan(6);
  ASSERT_EQ(table_reused.subFeatures().size(), 8u);  // six of the big pair, two of this one
  ASSERT_EQ(kept_fresh.size(), 2u);                  // the two closed corners
  for (std::size_t i = 0; i < kept_fresh.size(); ++i) {
    EXPECT_EQ(table_reused.subFeatures()[6 + i], table_fresh.subFeatures()[i]);
    EXPECT_EQ(kept_reused[i].shear_force, kept_fresh[i].shear_force);
    EXPECT_EQ(kept_reused[i].normal, kept_fresh[i].normal);
  }
  EXPECT_EQ(table_fresh.subFeatures()[0], (particles::SubFeature{subs[1].feature}));
  // The newcomer (no history) got the vanished corner's shear, the carried one its own.
  EXPECT_GT(kept_fresh[0].shear_force.y(), 3.0);
  EXPECT_GT(kept_fresh[1].shear_force.x(), 2.0);
}

// A joint stiffness per area scales with the face overlap; line and point contacts keep kn.
TEST(SubContactLaw, JointStiffnessScalesWithTheArea) {
  auto k = law();
  k.jkn = 2e9;  // Pa/m
  std::vector<particles::SubEntry> kept;
  const auto f = subContactForces(face(square(1e-4), 0.25), {}, {}, still(), kMass, kDt, k, kept);
  EXPECT_NEAR(f.force.z(), 2e9 * 0.25 * 1e-4, 1e-6);
  const std::vector<SubContact> point{{0, Vec3::Zero(), Vec3::UnitZ(), 1e-4, 1.0}};
  const auto p =
      subContactForces({ContactArea::kPoint, 0.0, point}, {}, {}, still(), kMass, kDt, k, kept);
  EXPECT_NEAR(p.force.z(), kKn * 1e-4, 1e-6);
}

// A joint's strengths are stresses over the contact's area A (jointCoefficients): sliding fast,
// the total shear is mu N + c A, whatever the area's split into corners; and the same stress on
// a twice larger area carries twice the cohesion.
TEST(SubContactLaw, JointCohesionIsAStressOverTheArea) {
  const JointParameters joint{JointLaw::kCoulomb, {1e9, 5e8, 30.0, 2e4, 0.0}};
  const LawCoefficients k = jointCoefficients(joint, law());
  PairKinematics kin = still();
  kin.va = Vec3(100, 0, 0);
  for (const double area : {1.0, 2.0}) {
    std::vector<particles::SubEntry> kept;
    const auto f = subContactForces(face(square(1e-4), area), {}, {}, kin, kMass, kDt, k, kept);
    EXPECT_TRUE(f.sliding);
    EXPECT_NEAR(f.normal, 1e9 * area * 1e-4, 1e-6) << "Kn = jkn A";
    EXPECT_NEAR(f.shear, std::tan(M_PI / 6) * f.normal + 2e4 * area, 1e-9 * f.shear) << area;
  }
}

// Tension: a corner apart by less than sigma_t / jkn pulls with its spring, kn_i g_i < 0; one
// apart by more carries nothing (and keeps its strength for the next step: the plain Coulomb
// joint). Without a tensile strength the open corners carry nothing, as for a material pair.
TEST(SubContactLaw, JointTensileStrengthLetsOpenCornersPull) {
  const double jkn = 1e9, sigma_t = 1e5;  // open gaps down to -1e-4 m pull
  LawCoefficients k =
      jointCoefficients({JointLaw::kCoulomb, {jkn, 5e8, 30.0, 0.0, sigma_t}}, law());
  const auto subs = square(0.4e-4, 3e-4);  // gaps -1.1e-4 (-y, beyond the limit), 1.9e-4 (+y)
  std::vector<particles::SubEntry> kept;
  auto f = subContactForces(face(subs), {}, {}, still(), kMass, kDt, k, kept);
  EXPECT_EQ(f.loaded, 2) << "corners beyond -sigma_t / jkn are open";
  const auto pulled = square(0.5e-4, 2.8e-4);  // gaps -0.9e-4 and 1.9e-4
  f = subContactForces(face(pulled), {}, {}, still(), kMass, kDt, k, kept);
  EXPECT_EQ(f.loaded, 4);
  EXPECT_NEAR(f.force.z(), 0.25 * jkn * 2 * (-0.9e-4 + 1.9e-4), 1e-6);
  EXPECT_NEAR(f.torque_a.x(), 0.25 * jkn * 2 * 0.5 * (1.9e-4 + 0.9e-4), 1e-6);
  k.tensile_strength = 0.0;
  f = subContactForces(face(pulled), {}, {}, still(), kMass, kDt, k, kept);
  EXPECT_EQ(f.loaded, 2);
  EXPECT_NEAR(f.force.z(), 0.25 * jkn * 2 * 1.9e-4, 1e-6);
}

}  // namespace
}  // namespace polydem::dynamics
