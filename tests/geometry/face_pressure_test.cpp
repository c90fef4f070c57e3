// Hydrostatic pressure on a polygon (geometry/face_pressure.h) against hand formulas: a vertical
// rectangle reaching the surface (force gamma b h^2 / 2 at two thirds of the depth), the same
// rectangle deeper down and half out of the water, a right triangle (force gamma A h / 3, centre
// of pressure at depth h / 2 and a quarter of the base), a face entirely above the surface, and
// an inclined surface against the moment moved to another origin; at scales 1e-3 and 1e3.
#include "polydem/geometry/face_pressure.h"

#include <gtest/gtest.h>

#include <vector>

namespace polydem::geometry {
namespace {

constexpr double kGamma = 9810.0;  // N/m^3

std::vector<int> indices(std::size_t n) {
  std::vector<int> out(n);
  for (std::size_t i = 0; i < n; ++i) out[i] = static_cast<int>(i);
  return out;
}

PressureResultant resultant(const std::vector<Vec3>& polygon, const Vec3& normal, double level,
                            const Vec3& origin = Vec3::Zero()) {
  // p = gamma (level - z), about `origin`.
  LinearPressure p{origin, kGamma * (level - origin.z()), Vec3(0, 0, -kGamma)};
  return pressureResultant(polygon, indices(polygon.size()), normal, p);
}

// The face x = 0 of a body lying at x > 0 (outward normal -x), y in [0, b], z in [bottom, top],
// counter-clockwise seen from -x.
std::vector<Vec3> rectangle(double b, double bottom, double top) {
  return {Vec3(0, 0, top), Vec3(0, b, top), Vec3(0, b, bottom), Vec3(0, 0, bottom)};
}

void expectVec(const Vec3& got, const Vec3& want, double scale) {
  EXPECT_NEAR((got - want).norm(), 0.0, 1e-12 * scale)
      << got.transpose() << " vs " << want.transpose();
}

class FacePressure : public ::testing::TestWithParam<double> {};

TEST_P(FacePressure, RectangleFromTheSurfaceDown) {
  const double s = GetParam(), b = 2 * s, h = 3 * s;
  const auto r = resultant(rectangle(b, -h, 0), Vec3(-1, 0, 0), 0.0);
  const double force = kGamma * b * h * h / 2;
  expectVec(r.force, Vec3(force, 0, 0), force);  // into the body, against the normal
  // The centre of pressure at (0, b/2, -2h/3): moment r x F about the origin.
  expectVec(r.moment, Vec3(0, -2 * h / 3, -b / 2) * force, force * h);
  EXPECT_NEAR(r.wetted_area, b * h, 1e-12 * b * h);
  EXPECT_NEAR(r.load, force, 1e-12 * force);
}

TEST_P(FacePressure, RectangleDeepDown) {
  const double s = GetParam(), b = 2 * s, h = 3 * s, d = 5 * s;  // top d below the surface
  const Vec3 origin(1 * s, 0.5 * s, -d);
  const auto r = resultant(rectangle(b, -d - h, -d), Vec3(-1, 0, 0), 0.0, origin);
  const double force = kGamma * b * h * (d + h / 2);
  expectVec(r.force, Vec3(force, 0, 0), force);
  // Depth of the centre of pressure below the top: (h/2 d + h^2/3) / (d + h/2).
  const double below_top = (d * h / 2 + h * h / 3) / (d + h / 2);
  const Vec3 centre(0, b / 2, -d - below_top);
  expectVec(r.moment, (centre - origin).cross(Vec3(force, 0, 0)), force * h);
}

TEST_P(FacePressure, RectangleHalfOutOfTheWater) {
  const double s = GetParam(), b = 2 * s, h = 3 * s;
  const auto r = resultant(rectangle(b, -h, 0), Vec3(-1, 0, 0), -h / 2);
  const double wet = h / 2, force = kGamma * b * wet * wet / 2;
  expectVec(r.force, Vec3(force, 0, 0), force);
  expectVec(r.moment, Vec3(0, -h / 2 - 2 * wet / 3, -b / 2) * force, force * h);
  EXPECT_NEAR(r.wetted_area, b * wet, 1e-12 * b * h);
}

TEST_P(FacePressure, TriangleApexDown) {
  // (0,0,0), (0,b,0), (0,0,-h): width b (1 - depth/h) at each depth.
  const double s = GetParam(), b = 2 * s, h = 3 * s;
  const std::vector<Vec3> tri = {Vec3(0, 0, 0), Vec3(0, b, 0), Vec3(0, 0, -h)};
  const auto r = resultant(tri, Vec3(-1, 0, 0), 0.0);
  const double area = b * h / 2, force = kGamma * area * h / 3;
  expectVec(r.force, Vec3(force, 0, 0), force);
  // Centre of pressure: depth h/2 (int s^2 w / int s w), y = b/4 (int s w^2/2 / int s w).
  expectVec(r.moment, Vec3(0, b / 4, -h / 2).cross(Vec3(force, 0, 0)), force * h);
  EXPECT_NEAR(r.wetted_area, area, 1e-12 * area);
}

TEST_P(FacePressure, HorizontalTriangleUnderUniformPressure) {
  // The top face (normal +z) of a body, depth d: p = gamma d everywhere, at the centroid.
  const double s = GetParam(), d = 4 * s;
  const std::vector<Vec3> tri = {Vec3(0, 0, -d), Vec3(3 * s, 0, -d), Vec3(0, 2 * s, -d)};
  const auto r = resultant(tri, Vec3(0, 0, 1), 0.0);
  const double area = 3 * s * s, force = kGamma * d * area;
  expectVec(r.force, Vec3(0, 0, -force), force);
  expectVec(r.moment, Vec3(s, 2 * s / 3, -d).cross(Vec3(0, 0, -force)), force * d);
}

TEST_P(FacePressure, FaceAboveTheSurfaceCarriesNothing) {
  const double s = GetParam(), b = 2 * s, h = 3 * s;
  const auto r = resultant(rectangle(b, -h, 0), Vec3(-1, 0, 0), -h - s);
  EXPECT_EQ(r.force, Vec3::Zero());
  EXPECT_EQ(r.moment, Vec3::Zero());
  EXPECT_EQ(r.wetted_area, 0.0);
  // Touching the lowest edge only: still nothing.
  const auto touching = resultant(rectangle(b, -h, 0), Vec3(-1, 0, 0), -h);
  EXPECT_EQ(touching.wetted_area, 0.0);
  EXPECT_EQ(touching.force, Vec3::Zero());
}

TEST_P(FacePressure, InclinedSurfaceMomentFollowsTheOrigin) {
  // An inclined face under an inclined surface, partly wet: the force does not depend on the
  // origin the pressure is given about, and the moment moves as M' = M + (O - O') x F.
  const double s = GetParam();
  const Vec3 n = Vec3(1, 0.5, 2).normalized();
  const Vec3 u = n.cross(Vec3::UnitX()).normalized(), v = n.cross(u);
  const Vec3 c(0.3 * s, -0.2 * s, -0.5 * s);
  const std::vector<Vec3> quad = {c + s * (-u - v), c + s * (u - 0.5 * v), c + s * (u + v),
                                  c + s * (-0.5 * u + v)};
  const Vec3 gradient = kGamma * Vec3(0.2, -0.1, -1.0);  // z_surface = 0.2 x - 0.1 y
  const Vec3 o1 = Vec3::Zero(), o2 = Vec3(2 * s, -s, 0.5 * s);
  const LinearPressure p1{o1, 0.0, gradient};
  const LinearPressure p2{o2, gradient.dot(o2 - o1), gradient};
  const auto r1 = pressureResultant(quad, indices(4), n, p1);
  const auto r2 = pressureResultant(quad, indices(4), n, p2);
  ASSERT_GT(r1.wetted_area, 0.0);
  ASSERT_LT(r1.wetted_area, 0.99 * 3.0 * s * s);  // partly wet (the quad's area is 3 s^2)
  expectVec(r2.force, r1.force, r1.force.norm() * 1e3);
  expectVec(r2.moment, r1.moment + (o1 - o2).cross(r1.force), r1.force.norm() * s * 1e3);
  EXPECT_NEAR(r1.force.normalized().dot(-n), 1.0, 1e-12);
}

INSTANTIATE_TEST_SUITE_P(Scales, FacePressure, ::testing::Values(1e-3, 1.0, 1e3));

}  // namespace
}  // namespace polydem::geometry
