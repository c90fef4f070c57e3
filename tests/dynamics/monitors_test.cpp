// Kinetic energy, force accumulation, and the force ratio of Keissar eq. 3.2: its value on simple
// situations and its independence of the number of ranks (run on 1, 2 and 3 ranks).
#include "polydem/dynamics/monitors.h"

#include <gtest/gtest.h>
#include <mpi.h>

#include <cmath>
#include <vector>

#include "polydem/core/mpi_env.h"

namespace polydem::dynamics {
namespace {

TEST(Monitors, KineticEnergyIsTranslationalPlusRotational) {
  particles::Particle p;
  p.velocity = Vec3(1.0, -2.0, 0.5);
  p.orientation = Quat(Eigen::AngleAxisd(0.6, Vec3(0, 1, 1).normalized()));
  const MassProperties mass{4.0, Vec3(1.0, 2.0, 3.0)};
  const Vec3 w_body(0.5, -0.25, 2.0);
  p.angular_momentum = p.orientation * w_body.cwiseProduct(mass.principal_inertia);
  const double expected =
      0.5 * 4.0 * p.velocity.squaredNorm() + 0.5 * w_body.cwiseAbs2().dot(mass.principal_inertia);
  EXPECT_NEAR(kineticEnergy(p, mass), expected, 1e-14 * expected);
  p.flags = particles::kFixed;
  EXPECT_EQ(kineticEnergy(p, mass), 0.0);
}

TEST(Monitors, AccumulatorSumsForcesTorquesAndNorms) {
  ForceAccumulator acc;
  const Vec3 centroid(1, 1, 1);
  acc.addContact(Vec3(0, 0, 5), Vec3(2, 1, 0), centroid);
  acc.addContact(Vec3(-1, 2, 0), Vec3(1, 1, 2), centroid);
  acc.addBodyForce(Vec3(0, 0, -9.81));
  EXPECT_EQ(acc.force, Vec3(-1, 2, 5 - 9.81));
  const Vec3 torque = Vec3(1, 0, -1).cross(Vec3(0, 0, 5)) + Vec3(0, 0, 1).cross(Vec3(-1, 2, 0));
  EXPECT_NEAR((acc.torque - torque).norm(), 0.0, 1e-15);
  EXPECT_DOUBLE_EQ(acc.norm_sum, 5.0 + 3.0 + 9.81);
  acc.clear();
  EXPECT_EQ(acc.norm_sum, 0.0);
}

TEST(Monitors, ForceRatioOfSimpleStates) {
  // A block resting on a plane: the contact balances gravity exactly, R = 0.
  ForceRatio resting;
  ForceAccumulator block;
  block.addContact(Vec3(0, 0, 19.62), Vec3(0, 0, -0.5), Vec3::Zero());
  block.addBodyForce(Vec3(0, 0, -19.62));
  resting.add(block);
  EXPECT_EQ(resting.value(), 0.0);
  // A free-falling block: everything is out of balance, R = 1.
  ForceRatio falling;
  ForceAccumulator free_block;
  free_block.addBodyForce(Vec3(0, 0, -19.62));
  falling.add(free_block);
  EXPECT_EQ(falling.value(), 1.0);
  // Nothing at all: R = 0.
  EXPECT_EQ(ForceRatio{}.value(), 0.0);
  // Two unequal forces: (|3 - 1|) / (3 + 1).
  ForceRatio half;
  ForceAccumulator pushed;
  pushed.addContact(Vec3(3, 0, 0), Vec3::Zero(), Vec3::Zero());
  pushed.addContact(Vec3(-1, 0, 0), Vec3::Zero(), Vec3::Zero());
  half.add(pushed);
  EXPECT_DOUBLE_EQ(half.value(), 0.5);
}

// Many particles spread over the ranks in an arbitrary way give the same bits as one rank summing
// them all, and match the definition evaluated in long double.
TEST(Monitors, ForceRatioIsTheSameOnAnyRankCount) {
  const int rank = mpi::rank(), size = mpi::size();
  const int n = 1000;
  std::vector<ForceAccumulator> particles(n);
  unsigned state = 2024;
  auto uniform = [&state] {
    state = state * 1664525u + 1013904223u;
    return (state >> 8) / double(1u << 24) - 0.5;
  };
  for (auto& acc : particles) {
    const int contacts = 1 + static_cast<int>((uniform() + 0.5) * 6);
    for (int c = 0; c < contacts; ++c) {
      // Forces over many orders of magnitude, so that the order of a plain sum would matter.
      const double scale = std::pow(10.0, 8.0 * (uniform() + 0.5));
      acc.addContact(scale * Vec3(uniform(), uniform(), uniform()), Vec3::Zero(), Vec3::Zero());
    }
    acc.addBodyForce(Vec3(0, 0, -9.81 * (uniform() + 1.0)));
  }
  ForceRatio serial;
  long double num = 0.0L, den = 0.0L;
  for (const auto& acc : particles) {
    serial.add(acc);
    num += manhattan(acc.force);
    den += acc.norm_sum;
  }
  ForceRatio distributed;
  // Scrambled ownership: particle i lives on rank (7 i + 3) mod size.
  for (int i = n - 1; i >= 0; --i) {
    if ((7 * i + 3) % size == rank) distributed.add(particles[i]);
  }
  distributed.allreduce(MPI_COMM_WORLD);
  EXPECT_EQ(distributed.value(), serial.value());
  EXPECT_EQ(distributed.unbalanced(), serial.unbalanced());
  EXPECT_EQ(distributed.applied(), serial.applied());
  EXPECT_NEAR(serial.value(), static_cast<double>(num / den), 1e-15);
  EXPECT_GT(serial.value(), 0.0);
  EXPECT_LT(serial.value(), 1.0);
}

}  // namespace
}  // namespace polydem::dynamics
