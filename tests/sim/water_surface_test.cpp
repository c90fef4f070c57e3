// The phreatic surface of [water] (sim/water.h): the plane through three points passes through
// them, a level surface is flat, and a table is interpolated linearly in time and held at its
// first and last rows outside them; a surface through six points whose table keeps them on a
// moving plane loads a face as that plane does at every time; a dry surface loads nothing.
#include <gtest/gtest.h>

#include "polydem/sim/water.h"

namespace polydem::sim {
namespace {

setup::WaterSpec plane(std::vector<double> times, std::vector<std::vector<double>> heights) {
  setup::WaterSpec w;
  w.enabled = true;
  w.points = {{{0.0, -1.0}}, {{0.5, 2.0}}, {{3.0, 0.25}}};
  w.times = std::move(times);
  w.heights = std::move(heights);
  return w;
}

TEST(WaterSurface, PlaneThroughThreePoints) {
  const auto w = plane({0.0}, {{1.0, -0.5, 2.0}});
  const auto s = phreaticSurface(w, 0.0);
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_NEAR(s.at(w.points[i][0], w.points[i][1]), w.heights[0][i], 1e-14) << "point " << i;
  }
}

TEST(WaterSurface, LevelSurfaceIsFlat) {
  setup::WaterSpec w;
  w.enabled = true;
  w.times = {0.0};
  w.heights = {{-2.5}};
  const auto s = phreaticSurface(w, 10.0);
  EXPECT_EQ(s.at(0, 0), -2.5);
  EXPECT_EQ(s.at(1e3, -7), -2.5);
  EXPECT_EQ(s.slope_x, 0.0);
  EXPECT_EQ(s.slope_y, 0.0);
}

TEST(WaterSurface, TableInterpolatedAndHeld) {
  const auto w = plane({1.0, 3.0, 4.0}, {{0.0, 0.0, 0.0}, {2.0, 4.0, -2.0}, {1.0, 1.0, 1.0}});
  auto at = [&](double t, std::size_t i) {
    return phreaticSurface(w, t).at(w.points[i][0], w.points[i][1]);
  };
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_NEAR(at(0.0, i), 0.0, 1e-14);                    // before the first row: held
    EXPECT_NEAR(at(2.0, i), 0.5 * w.heights[1][i], 1e-14);  // half way to the second
    EXPECT_NEAR(at(3.5, i), 0.5 * (w.heights[1][i] + 1.0), 1e-14);
    EXPECT_NEAR(at(9.0, i), 1.0, 1e-14);  // after the last row: held
  }
}

TEST(WaterSurface, SixPointsOnAMovingPlaneLoadLikeThePlane) {
  // Rows of heights on the planes z = a + b x + c y, the six points over [0, 4] x [0, 3].
  const double rows[3][3] = {{0.5, 0.1, -0.2}, {1.5, -0.3, 0.25}, {1.0, 0.0, 0.0}};
  setup::WaterSurfaceSpec six, three;
  six.points = {{{0, 0}}, {{2, 0.2}}, {{4, 0}}, {{4, 3}}, {{1.5, 2.2}}, {{0, 3}}};
  three.points = {{{0, 0}}, {{4, 0}}, {{0, 3}}};
  six.times = three.times = {0.0, 2.0, 5.0};
  for (const auto& r : rows) {
    auto heights = [&](const setup::WaterSurfaceSpec& w) {
      std::vector<double> z;
      for (const auto& p : w.points) z.push_back(r[0] + r[1] * p[0] + r[2] * p[1]);
      return z;
    };
    six.heights.push_back(heights(six));
    three.heights.push_back(heights(three));
  }
  // A face inclined in both directions, inside the hull, partly below the surface.
  // On the plane z = -0.5 + 0.3 x + 0.35 y.
  auto on = [](double x, double y) { return Vec3(x, y, -0.5 + 0.3 * x + 0.35 * y); };
  const std::vector<Vec3> face{on(0.5, 0.5), on(3.5, 0.8), on(3.2, 2.6), on(0.8, 2.4)};
  const Vec3 normal = (face[1] - face[0]).cross(face[2] - face[0]).normalized();
  const std::vector<int> polygon{0, 1, 2, 3};
  const Vec3 c(2.0, 1.5, -1.0);
  const double area = 0.5 * (face[2] - face[0]).cross(face[3] - face[1]).norm();
  int partly_dry = 0;
  for (const double t : {-1.0, 0.0, 1.0, 2.0, 3.7, 5.0, 8.0}) {
    const auto want = waterOnFace(three, 9810.0, t, face, polygon, normal, c);
    const auto got = waterOnFace(six, 9810.0, t, face, polygon, normal, c);
    ASSERT_GT(want.load, 0.0) << "t = " << t;
    partly_dry += want.wetted_area < 0.99 * area;
    EXPECT_NEAR(got.load, want.load, 1e-12 * want.load) << "t = " << t;
    EXPECT_NEAR((got.force - want.force).norm(), 0.0, 1e-12 * want.load) << "t = " << t;
    EXPECT_NEAR((got.moment - want.moment).norm(), 0.0, 1e-11 * want.load) << "t = " << t;
  }
  EXPECT_GT(partly_dry, 0);  // the line p = 0 crosses the face
  six.dry = true;
  EXPECT_EQ(waterOnFace(six, 9810.0, 1.0, face, polygon, normal, c).load, 0.0);
}

}  // namespace
}  // namespace polydem::sim
