// The bolt force law at a joint (dynamics/bolt_law.h): elastic loading, yield, elastic unloading
// from the plastic state, compression, shear yield with its slip kept, and breaking for good.
#include "polydem/dynamics/bolt_law.h"

#include <gtest/gtest.h>

#include <cmath>

namespace polydem::dynamics {
namespace {

BoltLaw law() {
  BoltLaw l;
  l.axial_stiffness = 2e6;  // N/m
  l.axial_yield = 5e3;      // N: yields at 2.5 mm
  l.shear_stiffness = 1e6;  // N/m
  l.shear_yield = 2e3;      // N: yields at 2 mm
  return l;
}

const Vec3 kAxis = Vec3(0, 0, -1);  // from the first block into the second

TEST(BoltLaw, ElasticInTensionAndPullsTheFirstBlockTowardsTheSecond) {
  BoltJointState s;
  // The second block moved 1 mm along the axis away from the first: elongation, tension.
  const auto f = boltJointForce(law(), kAxis, 1e-3 * kAxis, s);
  EXPECT_DOUBLE_EQ(f.axial, 2e3);
  EXPECT_TRUE(f.onFirst(kAxis).isApprox(2e3 * kAxis));
  EXPECT_EQ(s.axial_plastic, 0.0);
  EXPECT_FALSE(f.broke_now);
}

TEST(BoltLaw, YieldsThenUnloadsElastically) {
  BoltJointState s;
  auto f = boltJointForce(law(), kAxis, 4e-3 * kAxis, s);  // 4 mm: past yield (2.5 mm)
  EXPECT_DOUBLE_EQ(f.axial, 5e3);
  EXPECT_NEAR(s.axial_plastic, 1.5e-3, 1e-15);
  f = boltJointForce(law(), kAxis, 4e-3 * kAxis, s);  // held: still at yield, no new slip
  EXPECT_DOUBLE_EQ(f.axial, 5e3);
  EXPECT_NEAR(s.axial_plastic, 1.5e-3, 1e-15);
  f = boltJointForce(law(), kAxis, 3e-3 * kAxis, s);  // back 1 mm: elastic unloading
  EXPECT_NEAR(f.axial, 5e3 - 2e6 * 1e-3, 1e-9);
  EXPECT_NEAR(s.axial_plastic, 1.5e-3, 1e-15);
  f = boltJointForce(law(), kAxis, Vec3::Zero(), s);  // back to the start: compression
  EXPECT_NEAR(f.axial, -2e6 * 1.5e-3, 1e-9);
}

TEST(BoltLaw, CompressionIsCappedAtTheYieldForce) {
  BoltJointState s;
  const auto f = boltJointForce(law(), kAxis, -4e-3 * kAxis, s);
  EXPECT_DOUBLE_EQ(f.axial, -5e3);
  EXPECT_NEAR(s.axial_plastic, -1.5e-3, 1e-15);
}

TEST(BoltLaw, PretensionActsAtZeroDisplacement) {
  BoltLaw l = law();
  l.pretension = 3e3;
  BoltJointState s;
  EXPECT_DOUBLE_EQ(boltJointForce(l, kAxis, Vec3::Zero(), s).axial, 3e3);
  // 1 mm more elongation reaches the yield force exactly, 2 mm goes past it.
  EXPECT_DOUBLE_EQ(boltJointForce(l, kAxis, 1e-3 * kAxis, s).axial, 5e3);
  EXPECT_DOUBLE_EQ(boltJointForce(l, kAxis, 2e-3 * kAxis, s).axial, 5e3);
  EXPECT_NEAR(s.axial_plastic, 1e-3, 1e-15);
}

TEST(BoltLaw, ShearResistsTheSlipAndYieldsWithItsSlipKept) {
  BoltJointState s;
  const Vec3 slip(1, 0, 0);  // the second block slides along +x, across the bolt
  auto f = boltJointForce(law(), kAxis, 1e-3 * slip, s);
  EXPECT_DOUBLE_EQ(f.axial, 0.0);
  EXPECT_TRUE(f.shear.isApprox(1e3 * slip));         // on the first block: dragged along the slip
  f = boltJointForce(law(), kAxis, 5e-3 * slip, s);  // past the shear yield (2 mm)
  EXPECT_NEAR(f.shear.norm(), 2e3, 1e-9);
  EXPECT_NEAR(s.shear_plastic.x(), 3e-3, 1e-15);
  f = boltJointForce(law(), kAxis, 4e-3 * slip, s);  // back 1 mm: elastic, 1 kN
  EXPECT_NEAR(f.shear.x(), 1e3, 1e-9);
  // The axial part of a displacement does not load the shear spring.
  BoltJointState t;
  f = boltJointForce(law(), kAxis, 1e-3 * slip + 1e-3 * kAxis, t);
  EXPECT_NEAR(f.shear.x(), 1e3, 1e-9);
  EXPECT_NEAR(f.axial, 2e3, 1e-9);
}

TEST(BoltLaw, BreaksForGoodAtTheUltimateElongation) {
  BoltLaw l = law();
  l.ultimate_elongation = 2e-3;
  BoltJointState s;
  auto f = boltJointForce(l, kAxis, 4e-3 * kAxis, s);  // plastic 1.5 mm: holds
  EXPECT_FALSE(f.broke_now);
  EXPECT_DOUBLE_EQ(f.axial, 5e3);
  f = boltJointForce(l, kAxis, 5e-3 * kAxis, s);  // plastic 2.5 mm: breaks
  EXPECT_TRUE(f.broke_now);
  EXPECT_TRUE(s.broken);
  EXPECT_EQ(f.onFirst(kAxis), Vec3::Zero());
  f = boltJointForce(l, kAxis, 1e-3 * kAxis, s);  // unloaded: broken stays broken
  EXPECT_FALSE(f.broke_now);
  EXPECT_EQ(f.axial, 0.0);
  EXPECT_EQ(f.shear, Vec3::Zero());
}

}  // namespace
}  // namespace polydem::dynamics
