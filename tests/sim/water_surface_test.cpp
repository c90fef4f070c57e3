// The phreatic surface of [water] (sim/water.h): the plane through three points passes through
// them, a level surface is flat, and a table is interpolated linearly in time and held at its
// first and last rows outside them.
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

}  // namespace
}  // namespace polydem::sim
