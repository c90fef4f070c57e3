// The contact law on situations with an analytical answer: normal spring and potential force,
// viscous normal damping, shear built by increments up to the Coulomb cap, shear carried with a
// rotating contact plane, first contact, reset, and independence of the length unit.
#include "polydem/dynamics/contact_law.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "polydem/core/error.h"

namespace polydem::dynamics {
namespace {

contact::Contact penaltyContact(const Vec3& normal, double depth) {
  contact::Contact c;
  c.touching = true;
  c.normal = normal.normalized();
  c.depth = depth;
  c.model = contact::ForceModel::kPenalty;
  return c;
}

particles::ContactProperties properties(double kn, double ks, double phi_deg, double cohesion,
                                        double damping = 0.0) {
  particles::ContactProperties p;
  p.kn = kn;
  p.ks = ks;
  p.friction_angle = phi_deg;
  p.cohesion = cohesion;
  p.normal_damping = damping;
  return p;
}

TEST(ContactLaw, PenaltyNormalForceIsKnTimesDepthAlongTheNormal) {
  const Vec3 n = Vec3(1, -2, 2) / 3.0;
  const auto c = penaltyContact(n, 2e-4);
  const auto k = lawCoefficients(properties(3e8, 1e8, 30, 0));
  particles::PairHistory h;
  const ContactForce f = contactForce(c, Vec3::Zero(), 10.0, 1e-4, k, h);
  EXPECT_DOUBLE_EQ(f.normal, 3e8 * 2e-4);
  EXPECT_DOUBLE_EQ(f.normal_elastic, 3e8 * 2e-4);
  EXPECT_NEAR((f.force - 6e4 * n).norm(), 0.0, 1e-12 * 6e4);
  EXPECT_EQ(f.shear, 0.0);
  EXPECT_FALSE(f.sliding);
  EXPECT_EQ(h.touching, 1u);
  EXPECT_EQ(h.normal, c.normal);
}

TEST(ContactLaw, PotentialNormalForceIsPenaltyTimesPotential) {
  contact::Contact c;
  c.touching = true;
  c.normal = Vec3::UnitZ();
  c.depth = 1e-5;
  c.model = contact::ForceModel::kPotential;
  c.potential = 3e-6;  // m^2
  auto p = properties(0.0, 1e8, 30, 0);
  p.penalty = 2e9;  // Pa (Zhao section 5.3)
  particles::PairHistory h;
  const ContactForce f = contactForce(c, Vec3::Zero(), 1.0, 1e-5, lawCoefficients(p), h);
  EXPECT_DOUBLE_EQ(f.normal, 2e9 * 3e-6);  // Zhao eq. 13
  EXPECT_DOUBLE_EQ(f.force.z(), 2e9 * 3e-6);
}

TEST(ContactLaw, ViscousDampingResistsApproachAndNeverPulls) {
  const double kn = 1e7, m = 4.0, zeta = 0.3, depth = 1e-4;
  const auto k = lawCoefficients(properties(kn, 0.0, 0, 0, zeta));
  const auto c = penaltyContact(Vec3::UnitZ(), depth);
  const double c_crit = 2.0 * std::sqrt(m * kn);
  particles::PairHistory h;
  // A approaches B (moves against the normal): the dashpot adds to the spring.
  ContactForce f = contactForce(c, Vec3(0, 0, -0.01), m, 1e-5, k, h);
  EXPECT_NEAR(f.normal, kn * depth + zeta * c_crit * 0.01, 1e-12 * f.normal);
  EXPECT_EQ(f.normal_elastic, kn * depth);
  // A separates slowly: the dashpot subtracts.
  f = contactForce(c, Vec3(0, 0, 0.01), m, 1e-5, k, h);
  EXPECT_NEAR(f.normal, kn * depth - zeta * c_crit * 0.01, 1e-12 * kn * depth);
  // A separates fast: the total would pull, it is clamped to zero.
  f = contactForce(c, Vec3(0, 0, 10.0), m, 1e-5, k, h);
  EXPECT_EQ(f.normal, 0.0);
  EXPECT_EQ(f.force, Vec3::Zero());
}

TEST(ContactLaw, PotentialDampingUsesTheSecantStiffness) {
  contact::Contact c;
  c.touching = true;
  c.normal = Vec3::UnitZ();
  c.depth = 2e-5;
  c.model = contact::ForceModel::kPotential;
  c.potential = 4e-6;
  auto p = properties(0.0, 0.0, 0, 0, 0.2);
  p.penalty = 1e9;
  const double m = 3.0, vn = -0.05;
  particles::PairHistory h;
  const ContactForce f = contactForce(c, Vec3(0, 0, vn), m, 1e-6, lawCoefficients(p), h);
  const double f_el = 1e9 * 4e-6, k_secant = f_el / 2e-5;
  EXPECT_NEAR(f.normal, f_el - 2.0 * 0.2 * std::sqrt(m * k_secant) * vn, 1e-12 * f.normal);
}

// A block pressed with a constant overlap and dragged at constant tangential speed u: the shear
// force grows by ks u dt per step (opposing the motion) until it reaches fn tan(phi) + C, then
// stays on the cap with the sliding flag set.
TEST(ContactLaw, DragBuildsShearUpToTheCoulombCapThenSlides) {
  const double kn = 2e8, ks = 1.5e8, phi = 25.0, cohesion = 40.0, depth = 3e-5;
  const double u = 0.02, dt = 1e-5;
  const Vec3 n = Vec3(0, 1, 1).normalized();
  const Vec3 t_dir = Vec3(1, 0, 0);  // tangent to the plane
  const auto k = lawCoefficients(properties(kn, ks, phi, cohesion));
  const auto c = penaltyContact(n, depth);
  const double fn = kn * depth;
  const double cap = fn * std::tan(degToRad(phi)) + cohesion;
  const int stick_steps = static_cast<int>(std::floor(cap / (ks * u * dt)));
  ASSERT_GT(stick_steps, 10);
  particles::PairHistory h;
  // Normal velocity too: it must not enter the shear.
  const Vec3 v_rel = u * t_dir + 0.003 * n;
  for (int step = 1; step <= stick_steps + 20; ++step) {
    const ContactForce f = contactForce(c, v_rel, 1.0, dt, k, h);
    if (step <= stick_steps) {
      const double expected = ks * u * dt * step;  // ks * (tangential displacement)
      EXPECT_NEAR(f.shear, expected, 1e-12 * cap) << "step " << step;
      EXPECT_FALSE(f.sliding) << "step " << step;
    } else {
      EXPECT_NEAR(f.shear, cap, 1e-12 * cap) << "step " << step;
      EXPECT_TRUE(f.sliding) << "step " << step;
    }
    // The shear on A opposes A's tangential motion and lies in the contact plane.
    EXPECT_NEAR((h.shear_force + f.shear * t_dir).norm(), 0.0, 1e-12 * cap);
    EXPECT_NEAR(f.force.dot(n), fn, 1e-12 * fn);
  }
  // Reversing the drag unloads elastically from the cap: one step back takes ks u dt off.
  const ContactForce back = contactForce(c, -u * t_dir, 1.0, dt, k, h);
  EXPECT_NEAR(back.shear, cap - ks * u * dt, 1e-12 * cap);
  EXPECT_FALSE(back.sliding);
}

TEST(ContactLaw, CohesionAloneHoldsAContactWithoutNormalForce) {
  const auto k = lawCoefficients(properties(1e8, 1e8, 30, 5.0));
  const auto c = penaltyContact(Vec3::UnitZ(), 0.0);  // touching, no overlap
  particles::PairHistory h;
  const ContactForce f = contactForce(c, Vec3(1.0, 0, 0), 1.0, 1e-3, k, h);
  EXPECT_EQ(f.normal, 0.0);
  EXPECT_DOUBLE_EQ(f.shear, 5.0);
  EXPECT_TRUE(f.sliding);
  EXPECT_DOUBLE_EQ(f.force.x(), -5.0);
}

TEST(ContactLaw, FrictionOverrideReplacesTheFrictionAngle) {
  const auto p = properties(1e8, 1e8, 20, 0);
  EXPECT_DOUBLE_EQ(lawCoefficients(p).tan_friction, std::tan(degToRad(20.0)));
  EXPECT_DOUBLE_EQ(lawCoefficients(p, 89.0).tan_friction, std::tan(degToRad(89.0)));
  EXPECT_THROW(lawCoefficients(p, 90.0), Error);
  EXPECT_THROW(lawCoefficients(properties(-1.0, 1e8, 20, 0)), Error);
}

TEST(ContactLaw, RotateShearIsTheSmallestRotationOfTheNormal) {
  // z -> x is a quarter turn about +y: x goes to -z, y stays.
  EXPECT_NEAR((rotateShear(Vec3(3, 0, 0), Vec3::UnitZ(), Vec3::UnitX()) - Vec3(0, 0, -3)).norm(),
              0.0, 1e-15);
  EXPECT_NEAR((rotateShear(Vec3(0, 2, 0), Vec3::UnitZ(), Vec3::UnitX()) - Vec3(0, 2, 0)).norm(),
              0.0, 1e-15);
  // Against an explicit rotation matrix, for a generic pair of normals.
  const Vec3 n0 = Vec3(0.3, -0.4, 0.5).normalized(), n1 = Vec3(-0.2, 0.9, 0.1).normalized();
  const Vec3 axis = n0.cross(n1).normalized();
  const double angle = std::acos(n0.dot(n1));
  const Mat3 r = Eigen::AngleAxisd(angle, axis).toRotationMatrix();
  ASSERT_NEAR((r * n0 - n1).norm(), 0.0, 1e-14);
  Vec3 shear = Vec3(1.0, 2.0, -0.5);
  shear -= shear.dot(n0) * n0;
  EXPECT_NEAR((rotateShear(shear, n0, n1) - r * shear).norm(), 0.0, 1e-14 * shear.norm());
}

TEST(ContactLaw, RotateShearHandlesOppositeNormals) {
  const Vec3 n0 = Vec3(1, 2, 2) / 3.0;
  Vec3 shear = Vec3(2, -1, 0);  // tangent to n0
  ASSERT_NEAR(shear.dot(n0), 0.0, 1e-15);
  // Exactly opposite: the half turn about the shear's direction keeps it.
  EXPECT_EQ(rotateShear(shear, n0, -n0), shear);
  // Nearly opposite: still a rotation (magnitude kept, tangent to the new plane).
  for (double eps : {1e-3, 1e-6, 1e-9}) {
    const Vec3 tilt = Vec3(0, 1, -1).normalized();  // tangent to n0
    const Vec3 n1 = (-n0 + eps * tilt).normalized();
    const Vec3 out = rotateShear(shear, n0, n1);
    EXPECT_NEAR(out.norm(), shear.norm(), 1e-9 * shear.norm()) << eps;
    EXPECT_NEAR(out.dot(n1), 0.0, 1e-12 * shear.norm()) << eps;
  }
}

// The contact plane turns about a fixed axis lying in it by a small angle each step, without any
// relative motion: the shear force keeps its magnitude and turns with the plane (Zhao eq. 33).
TEST(ContactLaw, ShearTurnsWithARotatingContactPlane) {
  const auto k = lawCoefficients(properties(1e8, 1e8, 45, 1e9));  // cap far away
  const Vec3 axis = Vec3(1, 1, 0).normalized();
  const Vec3 n0 = Vec3(1, -1, 1).normalized();
  ASSERT_NEAR(axis.dot(n0), 0.0, 1e-15);
  particles::PairHistory h;
  // Build a shear with components both along the axis and across it.
  contactForce(penaltyContact(n0, 1e-4), Vec3(0.3, 0.1, 0.2), 1.0, 1e-3, k, h);
  const Vec3 shear0 = h.shear_force;
  ASSERT_GT(shear0.norm(), 0.0);
  const int steps = 5000;
  const double step_angle = 2e-4;
  for (int s = 1; s <= steps; ++s) {
    const Vec3 n = Eigen::AngleAxisd(s * step_angle, axis) * n0;
    contactForce(penaltyContact(n, 1e-4), Vec3::Zero(), 1.0, 1e-3, k, h);
  }
  const Mat3 total = Eigen::AngleAxisd(steps * step_angle, axis).toRotationMatrix();
  EXPECT_NEAR(h.shear_force.norm(), shear0.norm(), 1e-12 * shear0.norm());
  EXPECT_NEAR((h.shear_force - total * shear0).norm(), 0.0, 1e-10 * shear0.norm());
  EXPECT_NEAR(h.shear_force.dot(h.normal), 0.0, 1e-13 * shear0.norm());
}

TEST(ContactLaw, WanderingNormalKeepsShearTangentAndItsMagnitude) {
  const auto k = lawCoefficients(properties(1e8, 1e8, 45, 1e9));
  particles::PairHistory h;
  Vec3 n = Vec3::UnitZ();
  contactForce(penaltyContact(n, 1e-4), Vec3(0.4, -0.3, 0), 1.0, 1e-3, k, h);
  const double magnitude = h.shear_force.norm();
  unsigned state = 12345;
  auto uniform = [&state] {
    state = state * 1103515245u + 12345u;
    return (state >> 8) / double(1u << 24) - 0.5;
  };
  for (int s = 0; s < 20000; ++s) {
    n = (n + 0.05 * Vec3(uniform(), uniform(), uniform())).normalized();
    contactForce(penaltyContact(n, 1e-4), Vec3::Zero(), 1.0, 1e-3, k, h);
  }
  EXPECT_NEAR(h.shear_force.norm(), magnitude, 1e-11 * magnitude);
  EXPECT_NEAR(h.shear_force.dot(n), 0.0, 1e-14 * magnitude);
}

TEST(ContactLaw, FirstContactStartsFromZeroShearAndResetClears) {
  const auto k = lawCoefficients(properties(1e8, 2e8, 30, 0));
  particles::PairHistory h;
  h.shear_force = Vec3(5, 5, 5);  // stale values of a pair that was not touching
  h.normal = Vec3::UnitX();
  h.touching = 0;
  h.kernel.warm_valid = 1;
  h.kernel.warm_direction = Vec3(0, 1, 0);
  const double dt = 1e-4;
  const Vec3 v(0.1, 0, 0);
  contactForce(penaltyContact(Vec3::UnitZ(), 1e-3), v, 1.0, dt, k, h);
  EXPECT_NEAR((h.shear_force - (-2e8 * dt) * v).norm(), 0.0, 1e-12 * 2e8 * dt * 0.1);
  // A step without contact: no force, and the history is reset as by resetShear().
  contact::Contact apart;
  apart.touching = false;
  const ContactForce none = contactForce(apart, v, 1.0, dt, k, h);
  EXPECT_EQ(none.force, Vec3::Zero());
  EXPECT_EQ(none.normal, 0.0);
  EXPECT_EQ(h.shear_force, Vec3::Zero());
  EXPECT_EQ(h.normal, Vec3::Zero());
  EXPECT_EQ(h.touching, 0u);
  EXPECT_EQ(h.kernel.warm_valid, 1u);  // the kernel's warm start is kept
  EXPECT_EQ(h.kernel.warm_direction, Vec3(0, 1, 0));
}

// Lengths in mm or km instead of m (depth, velocity) with the same stiffness: every force scales
// with the length unit, sliding happens at the same step.
TEST(ContactLaw, IndependentOfTheLengthUnit) {
  const auto k = lawCoefficients(properties(1e8, 8e7, 30, 0, 0.1));
  const Vec3 n = Vec3(1, 2, 3).normalized();
  const Vec3 v = Vec3(0.5, -0.2, 0.1);
  std::vector<Vec3> reference;
  std::vector<bool> sliding;
  for (double scale : {1.0, 1e-3, 1e3}) {
    particles::PairHistory h;
    for (int s = 0; s < 200; ++s) {
      const Vec3 ns = Eigen::AngleAxisd(1e-3 * s, Vec3::UnitZ()) * n;
      const auto c = penaltyContact(ns, scale * 1e-4 * (1.0 + 0.01 * s));
      const ContactForce f = contactForce(c, scale * v, 2.0, 1e-5, k, h);
      if (scale == 1.0) {
        reference.push_back(f.force);
        sliding.push_back(f.sliding);
      } else {
        EXPECT_NEAR((f.force / scale - reference[s]).norm(), 0.0, 1e-12 * reference[s].norm());
        EXPECT_EQ(f.sliding, sliding[s]);
      }
    }
  }
}

}  // namespace
}  // namespace polydem::dynamics
