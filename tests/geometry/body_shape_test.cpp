// toBodyFrame: centroid to the origin, principal axes, exact coordinates for axis-aligned input.
#include "polydem/geometry/body_shape.h"

#include <gtest/gtest.h>

#include <cmath>

#include "polydem/geometry/shapes.h"
#include "polyhedron_checks.h"

namespace polydem::geometry {
namespace {

double offDiagonal(const Mat3& m) {
  return std::max({std::abs(m(0, 1)), std::abs(m(0, 2)), std::abs(m(1, 2))});
}

/// The result puts the body-frame shape back onto the input: x_input = R x_body + c.
void expectReproducesInput(const BodyFrameResult& r, const ConvexPolyhedron& input) {
  const Mat3 rot = r.rotation.toRotationMatrix();
  const auto& body = r.shape.polyhedron->vertices();
  ASSERT_EQ(body.size(), input.vertices().size());
  for (std::size_t i = 0; i < body.size(); ++i) {
    EXPECT_LT((rot * body[i] + r.centroid - input.vertices()[i]).norm(),
              1e-14 * (input.lengthScale() + input.centroid().norm()));
  }
  const auto back = r.shape.polyhedron->transformed(rot, r.centroid);
  EXPECT_LT((back.inertia() - input.inertia()).norm(), 1e-14 * input.inertia().norm());
}

void expectBodyFrame(const BodyFrameResult& r) {
  const auto& p = *r.shape.polyhedron;
  EXPECT_EQ(p.centroid(), Vec3::Zero());
  EXPECT_LE(offDiagonal(p.inertia()), 1e-12 * p.inertia().diagonal().maxCoeff());
  EXPECT_NEAR(r.rotation.norm(), 1.0, 1e-15);
  EXPECT_NEAR(r.rotation.toRotationMatrix().determinant(), 1.0, 1e-14);
  EXPECT_EQ(r.shape.principal_moments, p.inertia().diagonal());
  EXPECT_EQ(r.shape.volume, p.volume());
  EXPECT_EQ(r.shape.circumradius, p.circumradius());
  EXPECT_EQ(r.shape.inradius, p.inradius());
  testing::expectValidPolyhedron(p);
}

TEST(BodyShape, AxisAlignedBoxKeepsIdentityAndExactCoordinates) {
  const auto box = ConvexPolyhedron::fromPoints(shapes::box(Vec3(1, 2, 3), Vec3(2, 4, 7)));
  const auto r = toBodyFrame(box, "brick");
  EXPECT_EQ(r.shape.name, "brick");
  EXPECT_EQ(r.rotation.coeffs(), Quat::Identity().coeffs());
  EXPECT_EQ(r.centroid, Vec3(1.5, 3, 5));
  for (std::size_t i = 0; i < 8; ++i) {
    EXPECT_EQ(r.shape.polyhedron->vertices()[i], box.vertices()[i] - Vec3(1.5, 3, 5));
  }
  const double v = 1 * 2 * 4;
  EXPECT_NEAR(r.shape.principal_moments.x(), v * (4 + 16) / 12.0, 1e-14);
  EXPECT_NEAR(r.shape.principal_moments.y(), v * (1 + 16) / 12.0, 1e-14);
  EXPECT_NEAR(r.shape.principal_moments.z(), v * (1 + 4) / 12.0, 1e-14);
  expectBodyFrame(r);
  expectReproducesInput(r, box);
}

TEST(BodyShape, RotatedCuboidFindsItsPrincipalAxes) {
  std::mt19937_64 rng(31);
  const Vec3 half(0.5, 1.0, 1.5);
  const double v = 8 * half.prod();
  const Vec3 expected =
      v / 3.0 *
      Vec3(half.x() * half.x() + half.y() * half.y(), half.x() * half.x() + half.z() * half.z(),
           half.y() * half.y() + half.z() * half.z());
  for (int trial = 0; trial < 10; ++trial) {
    const Mat3 rot = testing::randomRotation(rng);
    const auto input = ConvexPolyhedron::fromPoints(
        testing::transformedPoints(shapes::boxAround(Vec3::Zero(), half), rot, Vec3(4, -2, 9)));
    const auto r = toBodyFrame(input);
    expectBodyFrame(r);
    expectReproducesInput(r, input);
    // Moments ascending: the axis along the longest side has the smallest moment.
    EXPECT_LT((r.shape.principal_moments - expected).norm(), 1e-13 * expected.norm());
    // The body-frame box is axis-aligned again: half-extents recovered.
    Vec3 extent = Vec3::Zero();
    for (const Vec3& x : r.shape.polyhedron->vertices()) extent = extent.cwiseMax(x.cwiseAbs());
    EXPECT_LT((extent - Vec3(half.z(), half.y(), half.x())).norm(), 1e-14);
    // Deterministic: the same input gives the same bits.
    const auto again = toBodyFrame(input);
    EXPECT_EQ(again.rotation.coeffs(), r.rotation.coeffs());
    EXPECT_EQ(again.shape.polyhedron->vertices(), r.shape.polyhedron->vertices());
  }
}

TEST(BodyShape, IsotropicShapesKeepTheirOrientation) {
  std::mt19937_64 rng(2);
  const Mat3 rot = testing::randomRotation(rng);
  for (const auto& points : {shapes::cube(1.0), shapes::tetrahedron(1.0), shapes::icosahedron(2.0),
                             shapes::dodecahedron(0.5)}) {
    const auto input =
        ConvexPolyhedron::fromPoints(testing::transformedPoints(points, rot, Vec3(1, 1, 1)));
    const auto r = toBodyFrame(input);
    EXPECT_EQ(r.rotation.coeffs(), Quat::Identity().coeffs());
    expectBodyFrame(r);
    expectReproducesInput(r, input);
  }
}

TEST(BodyShape, SquarePrismWithTwoEqualMomentsGetsItsAxisRight) {
  std::mt19937_64 rng(12);
  for (int trial = 0; trial < 5; ++trial) {
    const Mat3 rot = testing::randomRotation(rng);
    // Long square rod along z: the smallest moment is about its axis, the other two are equal.
    const auto input = ConvexPolyhedron::fromPoints(testing::transformedPoints(
        shapes::boxAround(Vec3::Zero(), Vec3(0.2, 0.2, 1.0)), rot, Vec3(0, 3, 0)));
    const auto r = toBodyFrame(input);
    expectBodyFrame(r);
    expectReproducesInput(r, input);
    const Mat3 axes = r.rotation.toRotationMatrix();
    EXPECT_NEAR(std::abs(axes.col(0).dot(rot.col(2))), 1.0, 1e-12);
    EXPECT_NEAR(r.shape.principal_moments.y(), r.shape.principal_moments.z(), 1e-14);
  }
  // A flat square plate: the largest moment (about the plate normal) is the single one.
  const Mat3 rot = testing::randomRotation(rng);
  const auto plate = ConvexPolyhedron::fromPoints(testing::transformedPoints(
      shapes::boxAround(Vec3::Zero(), Vec3(1.0, 1.0, 0.1)), rot, Vec3::Zero()));
  const auto r = toBodyFrame(plate);
  expectBodyFrame(r);
  EXPECT_NEAR(std::abs(r.rotation.toRotationMatrix().col(2).dot(rot.col(2))), 1.0, 1e-12);
}

TEST(BodyShape, IrregularPolyhedra) {
  for (std::uint64_t seed = 1; seed <= 10; ++seed) {
    const auto input =
        ConvexPolyhedron::fromPoints(shapes::randomConvex(30, seed, Vec3(1.0, 0.7, 0.3), 0.3));
    const auto r = toBodyFrame(input);
    expectBodyFrame(r);
    expectReproducesInput(r, input);
    EXPECT_LE(r.shape.principal_moments.x(), r.shape.principal_moments.y());
    EXPECT_LE(r.shape.principal_moments.y(), r.shape.principal_moments.z());
    EXPECT_NEAR(r.shape.volume, input.volume(), 1e-15 * input.volume());
    EXPECT_NEAR(r.shape.principal_moments.sum(), input.inertia().trace(),
                1e-14 * input.inertia().trace());
  }
}

}  // namespace
}  // namespace polydem::geometry
