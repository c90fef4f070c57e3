// Rigid motions, scaling and point containment of ConvexPolyhedron.
#include <gtest/gtest.h>

#include <cmath>

#include "polydem/core/error.h"
#include "polydem/geometry/convex_polyhedron.h"
#include "polydem/geometry/shapes.h"
#include "polyhedron_checks.h"

namespace polydem::geometry {
namespace {

TEST(ConvexPolyhedron, TransformedKeepsTopologyVolumeAndRotatesInertia) {
  std::mt19937_64 rng(8);
  const auto points = shapes::randomConvex(40, 3, Vec3(1.5, 1.0, 0.6), 0.2);
  const auto p = ConvexPolyhedron::fromPoints(points);
  for (int trial = 0; trial < 5; ++trial) {
    const Mat3 r = testing::randomRotation(rng);
    const Vec3 t(10.0 * trial, -3.0, 0.25);
    const auto moved = p.transformed(r, t);
    // Same indices and topology; geometry moved.
    ASSERT_EQ(moved.faces().size(), p.faces().size());
    for (std::size_t f = 0; f < p.faces().size(); ++f) {
      EXPECT_EQ(moved.faces()[f].vertices, p.faces()[f].vertices);
      EXPECT_LT((moved.faces()[f].normal - r * p.faces()[f].normal).norm(), 1e-15);
    }
    EXPECT_EQ(moved.volume(), p.volume());
    EXPECT_EQ(moved.circumradius(), p.circumradius());
    EXPECT_EQ(moved.inradius(), p.inradius());
    EXPECT_LT((moved.centroid() - (r * p.centroid() + t)).norm(), 1e-14 * (1 + t.norm()));
    EXPECT_LT((moved.inertia() - r * p.inertia() * r.transpose()).norm(),
              1e-15 * p.inertia().norm());
    testing::expectValidPolyhedron(moved);
    // Building the moved points from scratch agrees to round-off.
    const auto rebuilt = ConvexPolyhedron::fromPoints(testing::transformedPoints(points, r, t));
    ASSERT_EQ(rebuilt.faces().size(), p.faces().size());
    for (std::size_t f = 0; f < p.faces().size(); ++f) {
      EXPECT_EQ(rebuilt.faces()[f].vertices, p.faces()[f].vertices);
    }
    EXPECT_NEAR(rebuilt.volume(), p.volume(), 1e-14 * p.volume());
    EXPECT_LT((rebuilt.inertia() - moved.inertia()).norm(), 1e-13 * p.inertia().norm());
    EXPECT_LT((rebuilt.centroid() - moved.centroid()).norm(), 1e-14 * (1 + t.norm()));
  }
}

TEST(ConvexPolyhedron, TransformedRejectsReflectionsAndNonRotations) {
  const auto cube = ConvexPolyhedron::fromPoints(shapes::cube(1.0));
  EXPECT_THROW(cube.transformed(Vec3(1, 1, -1).asDiagonal(), Vec3::Zero()), GeometryError);
  EXPECT_THROW(cube.transformed(2.0 * Mat3::Identity(), Vec3::Zero()), GeometryError);
  EXPECT_THROW(cube.transformed(Mat3::Identity(), Vec3(0, std::nan(""), 0)), GeometryError);
}

TEST(ConvexPolyhedron, ScaledScalesLengthsAreasVolumeAndInertia) {
  const auto points = shapes::randomConvex(25, 6);
  const auto p = ConvexPolyhedron::fromPoints(points);
  for (double f : {1e-3, 0.5, 1e3}) {
    const auto s = p.scaled(f);
    EXPECT_NEAR(s.volume(), p.volume() * f * f * f, 1e-15 * s.volume());
    EXPECT_LT((s.inertia() - p.inertia() * std::pow(f, 5)).norm(), 1e-15 * s.inertia().norm());
    EXPECT_NEAR(s.circumradius(), f * p.circumradius(), 1e-15 * s.circumradius());
    EXPECT_NEAR(s.inradius(), f * p.inradius(), 1e-15 * s.inradius());
    EXPECT_NEAR(s.faces()[0].area, f * f * p.faces()[0].area, 1e-15 * s.faces()[0].area);
    std::vector<Vec3> scaled_points;
    for (const Vec3& x : points) scaled_points.push_back(f * x);
    const auto rebuilt = ConvexPolyhedron::fromPoints(scaled_points);
    EXPECT_NEAR(rebuilt.volume(), s.volume(), 1e-14 * s.volume());
    EXPECT_NEAR(rebuilt.inradius(), s.inradius(), 1e-12 * s.inradius());
    testing::expectValidPolyhedron(s);
  }
  EXPECT_THROW(p.scaled(0.0), GeometryError);
  EXPECT_THROW(p.scaled(-1.0), GeometryError);
}

TEST(ConvexPolyhedron, ContainsWithAndWithoutTolerance) {
  const auto box = ConvexPolyhedron::fromPoints(shapes::box(Vec3(0, 0, 0), Vec3(1, 2, 3)));
  EXPECT_TRUE(box.contains(box.centroid()));
  EXPECT_TRUE(box.contains(Vec3(1, 2, 3)));  // a corner is on the boundary
  EXPECT_TRUE(box.contains(Vec3(0.5, 1.0, 0.0)));
  EXPECT_FALSE(box.contains(Vec3(0.5, 1.0, -1e-9)));
  EXPECT_TRUE(box.contains(Vec3(0.5, 1.0, -1e-9), 2e-9));
  EXPECT_FALSE(box.contains(Vec3(1.5, 1.0, 1.0), 0.4));
}

TEST(ConvexPolyhedron, VertexFansGoCounterClockwiseSeenFromOutside) {
  // Apex of an upright square pyramid: seen from above its neighbours turn counter-clockwise.
  const auto pyr = ConvexPolyhedron::fromPoints(
      shapes::squarePyramid(Vec3::Zero(), 1.0, 1.0, shapes::Apex::kUp));
  const auto& ring = pyr.vertexNeighbours()[0];
  ASSERT_EQ(ring.size(), 4u);
  for (std::size_t k = 0; k < 4; ++k) {
    const Vec3 a = pyr.vertices()[ring[k]], b = pyr.vertices()[ring[(k + 1) % 4]];
    EXPECT_GT(a.cross(b).z(), 0.0);
  }
  testing::expectValidPolyhedron(pyr);
}

}  // namespace
}  // namespace polydem::geometry
