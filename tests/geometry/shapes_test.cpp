// The shape builders: what BENCHMARKS.md section C asks for, Platonic sizes, random polyhedra.
#include "polydem/geometry/shapes.h"

#include <gtest/gtest.h>

#include <cmath>

#include "polydem/core/error.h"
#include "polydem/geometry/convex_polyhedron.h"
#include "polyhedron_checks.h"

namespace polydem::geometry {
namespace {

using shapes::Apex;
using shapes::Platonic;

Vec3 lowest(const std::vector<Vec3>& points) {
  return *std::min_element(points.begin(), points.end(),
                           [](const Vec3& a, const Vec3& b) { return a.z() < b.z(); });
}

TEST(Shapes, BenchmarkCContactGeometries) {
  // C-VV: A apex down at (0, 0, -1e-5), base 1x1 at z = 1 - 1e-5; B apex up, base at z = -1,
  // turned 45 degrees.
  const auto a = shapes::squarePyramid(Vec3(0, 0, -1e-5), 1.0, 1.0, Apex::kDown);
  EXPECT_EQ(lowest(a), Vec3(0, 0, -1e-5));
  for (std::size_t i = 1; i < a.size(); ++i) {
    EXPECT_EQ(a[i].z(), 1.0 - 1e-5);
    EXPECT_EQ(a[i].cwiseAbs().head<2>(), Vec2(0.5, 0.5));
  }
  const auto b = shapes::squarePyramid(Vec3::Zero(), 1.0, 1.0, Apex::kUp, degToRad(45.0));
  for (std::size_t i = 1; i < b.size(); ++i) {
    EXPECT_EQ(b[i].z(), -1.0);
    EXPECT_NEAR(b[i].head<2>().norm(), std::sqrt(0.5), 1e-15);
    EXPECT_NEAR(std::min(std::abs(b[i].x()), std::abs(b[i].y())), 0.0, 1e-15);  // on the axes
  }
  // C-VE: ridge along x at z = 0, x in [-1, 1]; base y in [-0.5, 0.5] at z = -1.
  const auto ridge =
      ConvexPolyhedron::fromPoints(shapes::ridgePrism(Vec3(-1, 0, 0), Vec3(1, 0, 0), 0.5, 1.0));
  Vec3 lo = Vec3::Constant(1e9), hi = -lo;
  for (const Vec3& v : ridge.vertices()) {
    lo = lo.cwiseMin(v);
    hi = hi.cwiseMax(v);
  }
  EXPECT_EQ(lo, Vec3(-1, -0.5, -1));
  EXPECT_EQ(hi, Vec3(1, 0.5, 0));
  EXPECT_EQ(ridge.supportIndex(Vec3(0.1, 0.0, 1.0)), 1);  // the ridge end (1, 0, 0)
  // C-EEx: ridge along y.
  const auto ridge_y = shapes::ridgePrism(Vec3(0, -1, 0), Vec3(0, 1, 0), 0.5, 1.0);
  for (const Vec3& v : ridge_y) EXPECT_LE(std::abs(v.x()), 0.5);
  // C-EF / C-FF boxes.
  const auto box = ConvexPolyhedron::fromPoints(shapes::box(Vec3(-0.8, -2, -1), Vec3(3.2, 2, 0)));
  EXPECT_NEAR(box.volume(), 16.0, 1e-14);
  // C-EEp: unit cube turned 45 degrees about x, lowest edge along x at z = -1e-5.
  const Mat3 turn = Eigen::AngleAxisd(degToRad(45.0), Vec3::UnitX()).toRotationMatrix();
  const auto cube = ConvexPolyhedron::fromPoints(shapes::cube(1.0))
                        .transformed(turn, Vec3(0, 0, std::sqrt(0.5) - 1e-5));
  EXPECT_NEAR(lowest(cube.vertices()).z(), -1e-5, 1e-15);
}

TEST(Shapes, PlatonicSolidsHaveTheirEdgeAndCircumradius) {
  for (Platonic solid : {Platonic::kTetrahedron, Platonic::kCube, Platonic::kOctahedron,
                         Platonic::kDodecahedron, Platonic::kIcosahedron}) {
    const double edge = 0.7;
    const auto p = ConvexPolyhedron::fromPoints(shapes::platonic(solid, edge));
    for (const Edge& e : p.edges()) {
      EXPECT_NEAR((p.vertices()[e.v1] - p.vertices()[e.v0]).norm(), edge, 1e-15);
    }
    for (const Vec3& v : p.vertices()) {
      EXPECT_NEAR(v.norm(), edge * shapes::platonicCircumradiusPerEdge(solid), 1e-15);
    }
    const auto by_radius = shapes::platonicWithCircumradius(solid, 2.0);
    for (const Vec3& v : by_radius) EXPECT_NEAR(v.norm(), 2.0, 1e-15);
    testing::expectValidPolyhedron(p);
  }
  // Unit cube coordinates are exact.
  for (const Vec3& v : shapes::cube(1.0)) EXPECT_EQ(v.cwiseAbs(), Vec3::Constant(0.5));
}

TEST(Shapes, PrismsAndBoxes) {
  const auto hex = shapes::hexagonalPrism(0.3, 2.0);
  ASSERT_EQ(hex.size(), 12u);
  for (const Vec3& v : hex) {
    EXPECT_NEAR(v.head<2>().norm(), 0.3, 1e-15);
    EXPECT_EQ(std::abs(v.z()), 1.0);
  }
  const auto tri = shapes::prism({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)}, Vec3(0.2, 0, 1));
  EXPECT_NEAR(ConvexPolyhedron::fromPoints(tri).volume(), 0.5, 1e-15);
  const auto box = shapes::boxAround(Vec3(1, 1, 1), Vec3(0.5, 1, 2));
  EXPECT_EQ(box.front(), Vec3(0.5, 0, -1));
  EXPECT_EQ(box.back(), Vec3(1.5, 2, 3));
}

TEST(Shapes, RandomConvexIsDeterministicAndAllPointsAreCorners) {
  const auto a = shapes::randomConvex(100, 42, Vec3(1, 2, 3), 0.2);
  const auto b = shapes::randomConvex(100, 42, Vec3(1, 2, 3), 0.2);
  EXPECT_EQ(a, b);
  EXPECT_NE(a, shapes::randomConvex(100, 43, Vec3(1, 2, 3), 0.2));
  for (std::uint64_t seed = 0; seed < 5; ++seed) {
    const auto points = shapes::randomConvex(64, seed, Vec3(1, 0.5, 0.25), 0.5);
    BuildReport report;
    const auto p = ConvexPolyhedron::fromPoints(points, &report);
    EXPECT_EQ(p.vertices().size(), 64u);
    EXPECT_EQ(p.vertices(), points);  // vertices keep the input order
  }
}

TEST(Shapes, InvalidParametersThrow) {
  EXPECT_THROW(shapes::box(Vec3(0, 0, 0), Vec3(1, 0, 1)), GeometryError);
  EXPECT_THROW(shapes::cube(-1.0), GeometryError);
  EXPECT_THROW(shapes::cube(std::nan("")), GeometryError);
  EXPECT_THROW(shapes::ridgePrism(Vec3(0, 0, 0), Vec3(1, 0, 0.1), 0.5, 1.0), GeometryError);
  EXPECT_THROW(shapes::squarePyramid(Vec3::Zero(), 1.0, 0.0, Apex::kUp), GeometryError);
  EXPECT_THROW(shapes::randomConvex(3, 1), GeometryError);
  // Refused before the points are allocated (2e9 of them would take 48 GB).
  EXPECT_THROW(shapes::randomConvex(2'000'000'000, 1), GeometryError);
  EXPECT_THROW(shapes::randomConvex(shapes::kMaxRandomPoints + 1, 1), GeometryError);
  EXPECT_THROW(shapes::prism({Vec3(0, 0, 0), Vec3(1, 0, 0)}, Vec3(0, 0, 1)), GeometryError);
}

}  // namespace
}  // namespace polydem::geometry
