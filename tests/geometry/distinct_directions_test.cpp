// distinctDirections: the grid gives exactly the directions the pairwise comparison keeps, on
// sets with families of parallel directions (either sign) at and around the angle that decides.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "polydem/geometry/convex_polyhedron.h"
#include "polydem/geometry/distinct_directions.h"
#include "polydem/geometry/shapes.h"

namespace polydem::geometry {
namespace {

constexpr double kSin = ConvexPolyhedron::kParallelAxes;

// The definition: each direction against every one kept before it.
std::vector<int> reference(const std::vector<Vec3>& d, double sin_angle) {
  std::vector<int> kept;
  for (int i = 0; i < static_cast<int>(d.size()); ++i) {
    bool found = false;
    for (int k : kept) found = found || d[k].cross(d[i]).norm() <= sin_angle;
    if (!found) kept.push_back(i);
  }
  return kept;
}

Vec3 randomUnit(std::mt19937_64& rng) {
  std::normal_distribution<double> g;
  return Vec3(g(rng), g(rng), g(rng)).normalized();
}

// `base` turned by `angle` about a random axis perpendicular to it.
Vec3 tilted(const Vec3& base, double angle, std::mt19937_64& rng) {
  const Vec3 axis = base.cross(randomUnit(rng)).normalized();
  return Eigen::AngleAxisd(angle, axis) * base;
}

TEST(DistinctDirections, SameAsComparingEveryPair) {
  for (std::uint64_t seed = 1; seed <= 4; ++seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> factor(0.0, 3.0);
    std::vector<Vec3> d;
    std::vector<Vec3> bases;
    for (int i = 0; i < 3000; ++i) {
      // New directions, and copies of earlier ones tilted by 0 to 3 times the deciding angle,
      // half of them reversed; coordinate axes (cell boundaries at 0) among them.
      if (bases.empty() || i % 3 == 0) {
        bases.push_back(i % 50 == 0 ? Vec3::Unit(i % 3) : randomUnit(rng));
        d.push_back(bases.back());
      } else {
        const Vec3 base = bases[rng() % bases.size()];
        const Vec3 t = tilted(base, factor(rng) * kSin, rng);
        d.push_back(rng() % 2 ? t : Vec3(-t));
      }
    }
    const auto expected = reference(d, kSin);
    EXPECT_LT(expected.size(), d.size());      // some were parallel
    EXPECT_GT(expected.size(), bases.size());  // and some tilted copies were not
    EXPECT_EQ(distinctDirections(d, kSin), expected) << "seed " << seed;
  }
}

TEST(DistinctDirections, ManyFacedHullKeepsEveryFace) {
  // Points on a sphere: no two faces of their hull are parallel, so every face is an axis.
  const auto p = ConvexPolyhedron::fromPoints(shapes::randomConvex(3000, 5));
  EXPECT_EQ(p.axisFaces().size(), p.faces().size());
  std::vector<Vec3> normals;
  for (const Face& f : p.faces()) normals.push_back(f.normal);
  EXPECT_EQ(p.axisFaces(), reference(normals, kSin));
}

}  // namespace
}  // namespace polydem::geometry
