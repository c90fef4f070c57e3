// Support mapping (brute force and hill climbing) and splitting by a plane.
#include <gtest/gtest.h>

#include <cmath>

#include "polydem/geometry/convex_polyhedron.h"
#include "polydem/geometry/shapes.h"
#include "polyhedron_checks.h"

namespace polydem::geometry {
namespace {

int bruteForceSupport(const ConvexPolyhedron& p, const Vec3& d) {
  int best = 0;
  for (int i = 1; i < static_cast<int>(p.vertices().size()); ++i) {
    if (d.dot(p.vertices()[i]) > d.dot(p.vertices()[best])) best = i;
  }
  return best;
}

TEST(Support, EqualsBruteForceOnRandomDirections) {
  std::mt19937_64 rng(17);
  std::normal_distribution<double> normal;
  std::uniform_int_distribution<int> any(0, 1 << 20);
  for (int n : {8, 20, 32, 33, 100, 2000}) {
    const auto p = ConvexPolyhedron::fromPoints(shapes::randomConvex(n, n, Vec3(1.0, 0.5, 2.0)));
    ASSERT_EQ(static_cast<int>(p.vertices().size()), n);
    for (int i = 0; i < 500; ++i) {
      const Vec3 d(normal(rng), normal(rng), normal(rng));
      const int hint = any(rng) % n;
      const int expected = bruteForceSupport(p, d);
      EXPECT_EQ(p.supportIndex(d, hint), expected) << "n " << n;
      EXPECT_EQ(p.supportIndex(d), expected);
      EXPECT_EQ(p.support(d), p.vertices()[expected]);
    }
  }
}

TEST(Support, TiesGoToTheLowestIndex) {
  const auto cube = ConvexPolyhedron::fromPoints(shapes::cube(1.0));
  for (int axis = 0; axis < 3; ++axis) {
    for (double sign : {1.0, -1.0}) {
      const Vec3 d = sign * Vec3::Unit(axis);
      EXPECT_EQ(cube.supportIndex(d), bruteForceSupport(cube, d));
    }
  }
  // A 40-gon prism has 80 vertices: the hill climb ends on a face of maximisers.
  std::vector<Vec3> base;
  for (int k = 0; k < 40; ++k) {
    const double a = 2.0 * kPi * k / 40.0;
    base.emplace_back(std::cos(a), std::sin(a), 0.0);
  }
  const auto prism = ConvexPolyhedron::fromPoints(shapes::prism(base, Vec3(0, 0, 1)));
  ASSERT_EQ(prism.vertices().size(), 80u);
  for (int hint = 0; hint < 80; ++hint) {
    EXPECT_EQ(prism.supportIndex(Vec3(0, 0, 1), hint), bruteForceSupport(prism, Vec3(0, 0, 1)));
    EXPECT_EQ(prism.supportIndex(Vec3(0, 0, -1), hint), 0);
    EXPECT_EQ(prism.supportIndex(Vec3(1, 0, 0), hint), 0);  // edge (1,0,0)-(1,0,1)
  }
}

double volumeOf(const std::vector<Vec3>& points) {
  return points.empty() ? 0.0 : ConvexPolyhedron::fromPoints(points).volume();
}

TEST(Split, VolumesAddUpToTheWhole) {
  std::mt19937_64 rng(23);
  std::normal_distribution<double> normal;
  std::uniform_real_distribution<double> u(-0.8, 0.8);
  for (double scale : {1e-3, 1.0, 1e3}) {
    const auto p = ConvexPolyhedron::fromPoints(shapes::randomConvex(60, 2, Vec3(1.0, 0.8, 0.5)))
                       .scaled(scale);
    for (int i = 0; i < 50; ++i) {
      const Vec3 n = Vec3(normal(rng), normal(rng), normal(rng)).normalized();
      const Plane plane{n, scale * u(rng) * 0.5};
      const auto parts = p.split(plane);
      const double below = volumeOf(parts.below), above = volumeOf(parts.above);
      EXPECT_NEAR(below + above, p.volume(), 1e-12 * p.volume());
      for (const Vec3& x : parts.below) EXPECT_LE(plane.signedDistance(x), 1e-10 * p.lengthScale());
      for (const Vec3& x : parts.above)
        EXPECT_GE(plane.signedDistance(x), -1e-10 * p.lengthScale());
    }
  }
}

TEST(Split, CubeCutThroughVerticesAndFaces) {
  const auto cube = ConvexPolyhedron::fromPoints(shapes::cube(2.0));
  // Diagonal plane x = y through four vertices: two triangular prisms.
  const auto diagonal = cube.split(Plane{Vec3(1, -1, 0).normalized(), 0.0});
  ASSERT_EQ(diagonal.below.size(), 6u);
  ASSERT_EQ(diagonal.above.size(), 6u);
  EXPECT_NEAR(volumeOf(diagonal.below), 4.0, 1e-14);
  EXPECT_NEAR(volumeOf(diagonal.above), 4.0, 1e-14);
  // z = 0.5 gives boxes of heights 1.5 and 0.5.
  const auto level = cube.split(Plane{Vec3::UnitZ(), 0.5});
  EXPECT_EQ(level.below.size(), 8u);
  EXPECT_NEAR(volumeOf(level.below), 6.0, 1e-14);
  EXPECT_NEAR(volumeOf(level.above), 2.0, 1e-14);
  // A corner cut off: a tetrahedron.
  const auto corner = cube.split(Plane{Vec3(1, 1, 1).normalized(), std::sqrt(3.0) - 0.3});
  EXPECT_EQ(corner.above.size(), 4u);
  EXPECT_NEAR(volumeOf(corner.above), std::pow(0.3 * std::sqrt(3.0), 3) / 6.0, 1e-14);
}

TEST(Split, PlanesMissingOrGrazingLeaveOnePart) {
  const auto cube = ConvexPolyhedron::fromPoints(shapes::cube(1.0));
  const auto miss = cube.split(Plane{Vec3::UnitX(), 2.0});
  EXPECT_TRUE(miss.above.empty());
  EXPECT_EQ(miss.below, cube.vertices());
  const auto face = cube.split(Plane{Vec3::UnitX(), 0.5});  // on a face
  EXPECT_TRUE(face.above.empty());
  EXPECT_EQ(face.below.size(), 8u);
  // 1e-10 of the length scale into the cube: thinner than 1e-9, so no part.
  const auto graze = cube.split(Plane{Vec3::UnitX(), 0.5 - 1e-10 * cube.lengthScale()});
  EXPECT_TRUE(graze.above.empty());
  const auto other = cube.split(Plane{-Vec3::UnitX(), -0.5 + 1e-10 * cube.lengthScale()});
  EXPECT_TRUE(other.below.empty());
  EXPECT_EQ(other.above.size(), 8u);
  // 1e-8 in: a thin but real slab.
  const auto slab = cube.split(Plane{Vec3::UnitX(), 0.5 - 1e-8});
  EXPECT_NEAR(volumeOf(slab.above), 1e-8, 1e-14);
}

/// Cuts every block by every plane, as a rock mass is cut by joint sets.
std::vector<ConvexPolyhedron> cutByJoints(const ConvexPolyhedron& mass,
                                          const std::vector<Plane>& joints) {
  std::vector<ConvexPolyhedron> blocks{mass};
  for (const Plane& joint : joints) {
    std::vector<ConvexPolyhedron> next;
    for (const auto& block : blocks) {
      const auto parts = block.split(joint);
      for (const auto* part : {&parts.below, &parts.above}) {
        if (!part->empty()) next.push_back(ConvexPolyhedron::fromPoints(*part));
      }
    }
    blocks = std::move(next);
  }
  return blocks;
}

TEST(Split, RockMassCutByJointSetsKeepsItsVolume) {
  // Three joint sets, the first two through existing vertices of the grid they make (exactly
  // on the plane), the third dipping and crossing everything.
  const auto mass = ConvexPolyhedron::fromPoints(shapes::box(Vec3(0, 0, 0), Vec3(4, 3, 2)));
  std::vector<Plane> joints;
  for (int i = 1; i < 4; ++i) joints.push_back({Vec3::UnitX(), double(i)});
  for (int j = 1; j < 3; ++j) joints.push_back({Vec3::UnitY(), double(j)});
  const Vec3 dip = Vec3(0.3, -0.2, 1.0).normalized();
  for (int k = 0; k < 4; ++k) joints.push_back({dip, 0.2 + 0.5 * k});
  const auto blocks = cutByJoints(mass, joints);
  EXPECT_GE(blocks.size(), 12u);
  double total = 0.0;
  for (const auto& block : blocks) {
    total += block.volume();
    testing::expectValidPolyhedron(block);
  }
  EXPECT_NEAR(total, mass.volume(), 1e-12 * mass.volume());
  // The same cut in millimetres gives the same blocks, scaled.
  std::vector<Plane> joints_mm = joints;
  for (Plane& j : joints_mm) j.offset *= 1e-3;
  const auto blocks_mm = cutByJoints(mass.scaled(1e-3), joints_mm);
  ASSERT_EQ(blocks_mm.size(), blocks.size());
  for (std::size_t b = 0; b < blocks.size(); ++b) {
    EXPECT_EQ(blocks_mm[b].faces().size(), blocks[b].faces().size());
    EXPECT_NEAR(blocks_mm[b].volume(), 1e-9 * blocks[b].volume(),
                1e-12 * 1e-9 * blocks[b].volume());
  }
}

}  // namespace
}  // namespace polydem::geometry
