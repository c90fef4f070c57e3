// Support mapping (brute force and hill climbing) and splitting by a plane.
#include <gtest/gtest.h>

#include <cmath>

#include "geometry/convex_polyhedron.h"
#include "geometry/shapes.h"
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

}  // namespace
}  // namespace polydem::geometry
