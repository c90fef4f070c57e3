// How the multi-level grid groups particles: Zhao's fixed-ratio rule and the automatic plan.
#include "polydem/broadphase/level_plan.h"

#include <gtest/gtest.h>

#include <cmath>

#include "broadphase/scenes.h"
#include "polydem/broadphase/multilevel_grid.h"

namespace polydem::broadphase {
namespace {

using testing::randomScene;
using testing::Scene;

std::vector<LevelInfo> levelsOf(const Scene& s, const BroadPhaseParams& params, double margin) {
  MultiLevelGrid grid(params);
  std::vector<CandidatePair> out;
  grid.findPairs(s.view(), margin, out);
  return grid.levels();
}

// A dense jittered lattice of spheres with radius `big` (one in `every`) or `small` (the rest).
Scene twoSizes(int n, double big, double small, int every) {
  Scene s;
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> jitter(-0.1, 0.1);
  const int side = static_cast<int>(std::ceil(std::cbrt(n)));
  for (int i = 0; i < n; ++i) {
    const Vec3 c(i % side, (i / side) % side, i / (side * side));
    s.add(c + Vec3(jitter(rng), jitter(rng), jitter(rng)), i % every == 0 ? big : small);
  }
  s.finish(4);
  return s;
}

TEST(LevelPlan, RadiusBinsAreQuarterOctaves) {
  using detail::radiusBin;
  EXPECT_EQ(radiusBin(1.0, 1.0), 0);
  EXPECT_EQ(radiusBin(0.5, 1.0), 4);
  EXPECT_EQ(radiusBin(0.25, 1.0), 8);
  EXPECT_EQ(radiusBin(1.0 / std::pow(2.0, 0.25) * 1.000001, 1.0), 0);
  EXPECT_EQ(radiusBin(1.0 / std::pow(2.0, 0.25) * 0.999999, 1.0), 1);
  EXPECT_EQ(radiusBin(1.0 / std::pow(2.0, 0.75) * 0.999999, 1.0), 3);
  EXPECT_EQ(radiusBin(0.0, 1.0), detail::kBins - 1);
  EXPECT_EQ(radiusBin(1e-300, 1.0), detail::kBins - 1);
  EXPECT_EQ(radiusBin(3e-3, 3.0), radiusBin(3.0, 3e3));  // scale-free
}

TEST(LevelPlan, OneSizeIsOneLevel) {
  const Scene s = twoSizes(1000, 0.6, 0.6, 1);
  const auto levels = levelsOf(s, {}, 0.0);
  ASSERT_EQ(levels.size(), 1u);
  EXPECT_EQ(levels[0].count, 1000);
}

TEST(LevelPlan, TwoSizesTenApartAreTwoLevels) {
  // 10% big (radius 0.6) and 90% small (0.06), the mix of the P-BROADPHASE benchmark.
  const Scene s = twoSizes(2000, 0.6, 0.06, 10);
  const auto levels = levelsOf(s, {}, 0.0);
  ASSERT_EQ(levels.size(), 2u);
  EXPECT_EQ(levels[0].count, 200);
  EXPECT_EQ(levels[0].max_radius, 0.6);
  EXPECT_EQ(levels[1].count, 1800);
  EXPECT_EQ(levels[1].max_radius, 0.06);
  // Scale-free: the same plan in millimetres.
  Scene mm = s;
  for (auto& c : mm.centers) c *= 1e-3;
  for (auto& r : mm.radii) r *= 1e-3;
  const auto levels_mm = levelsOf(mm, {}, 0.0);
  ASSERT_EQ(levels_mm.size(), 2u);
  EXPECT_EQ(levels_mm[1].count, 1800);
}

TEST(LevelPlan, LoneHugeBodyGetsItsOwnLevel) {
  for (const double ratio : {1.0, 2.0}) {
    Scene s = randomScene({.n = 3000, .size_ratio = ratio, .solid_fraction = 0.3, .seed = 21});
    s.add(Vec3(0, 0, -1e3), 1e3);
    s.finish(5);
    const auto levels = levelsOf(s, {}, 0.01);
    ASSERT_GE(levels.size(), 2u);
    EXPECT_EQ(levels[0].count, 1);
    EXPECT_EQ(levels[0].max_radius, 1e3);
    // Nobody else is put in cells sized for the huge body.
    EXPECT_LE(levels[1].max_radius, ratio);
  }
}

TEST(LevelPlan, ZhaoRuleWithFixedGamma) {
  // Radii spread over a factor 100: with gamma 2 each level must hold one of Zhao's groups
  // D/gamma^k < r <= D/gamma^(k-1), the levels in decreasing k order, none empty.
  const Scene s = randomScene({.n = 3000, .size_ratio = 100.0, .solid_fraction = 0.2, .seed = 8});
  double max_r = 0.0;
  for (double r : s.radii) max_r = std::max(max_r, r);
  const double gamma = 2.0;
  auto group = [&](double r) { return std::floor(std::log(max_r / r) / std::log(gamma)); };
  const auto levels = levelsOf(s, {.gamma = gamma}, 0.0);
  EXPECT_EQ(levels.size(), 7u);  // factor 100 = 2^6.6: groups 0..6, all populated
  int total = 0;
  for (std::size_t k = 0; k < levels.size(); ++k) {
    EXPECT_GT(levels[k].count, 0);
    EXPECT_EQ(group(levels[k].max_radius), group(levels[k].min_radius)) << k;
    if (k > 0) {
      EXPECT_LT(group(levels[k - 1].min_radius), group(levels[k].max_radius));
    }
    total += levels[k].count;
  }
  EXPECT_EQ(total, 3000);
  // A cap on the number of levels: the last one takes all the rest.
  const auto capped = levelsOf(s, {.gamma = gamma, .levels = 3}, 0.0);
  ASSERT_EQ(capped.size(), 3u);
  EXPECT_EQ(group(capped[2].max_radius), 2.0);
  EXPECT_EQ(capped[0].count + capped[1].count + capped[2].count, 3000);
  const auto auto_capped = levelsOf(s, {.levels = 2}, 0.0);
  EXPECT_LE(auto_capped.size(), 2u);
}

}  // namespace
}  // namespace polydem::broadphase
