// The small candidate filters of overlap.h.
#include "polydem/broadphase/overlap.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>

namespace polydem::broadphase {
namespace {

TEST(Overlap, SpheresTouchingCountAndAreSymmetric) {
  const Vec3 a(0.0, 0.0, 0.0), b(3.0, 4.0, 0.0);  // distance 5 exactly
  EXPECT_TRUE(spheresOverlap(a, 2.0, b, 3.0));
  EXPECT_FALSE(spheresOverlap(a, 2.0, b, std::nextafter(5.0, 0.0) - 2.0));  // exact
  EXPECT_TRUE(spheresOverlap(a, 2.0, b, 2.5, 0.5));
  EXPECT_FALSE(spheresOverlap(a, 2.0, b, 2.5, 0.25));
  // Symmetric bit for bit, at scales where rounding matters.
  for (const double s : {1e-3, 0.1, 1e3}) {
    const Vec3 c(1e6 + 0.3 * s, -7.1 * s, 1e-3), d(1e6 - 0.4 * s, 0.2 * s, 0.7 * s);
    for (double r = 0.1 * s; r < 1.5 * s; r += 0.01 * s) {
      EXPECT_EQ(spheresOverlap(c, r, d, 0.3 * s, 0.01 * s),
                spheresOverlap(d, 0.3 * s, c, r, 0.01 * s));
    }
  }
}

TEST(Overlap, AabbOfCubeAndBoxTests) {
  std::array<Vec3, 8> cube;
  for (int k = 0; k < 8; ++k) cube[k] = Vec3(k & 1, (k >> 1) & 1, (k >> 2) & 1) + Vec3(2, 3, 4);
  const Aabb box = aabbOf(cube);
  EXPECT_EQ(box.lo, Vec3(2, 3, 4));
  EXPECT_EQ(box.hi, Vec3(3, 4, 5));

  Aabb other{Vec3(3, 3, 4), Vec3(4, 4, 5)};  // shares the face x = 3
  EXPECT_TRUE(aabbsOverlap(box, other));
  EXPECT_TRUE(aabbsOverlap(other, box));
  other.lo.x() = std::nextafter(3.0, 4.0);
  EXPECT_FALSE(aabbsOverlap(box, other));
  EXPECT_TRUE(aabbsOverlap(box, other, 1e-9));
  // Apart on one axis only is apart.
  const Aabb above{Vec3(2, 3, 5.5), Vec3(3, 4, 6)};
  EXPECT_FALSE(aabbsOverlap(box, above));
  EXPECT_TRUE(aabbsOverlap(box, above, 0.5));
  // The empty box overlaps nothing.
  const Aabb empty = aabbOf(std::span<const Vec3>());
  EXPECT_FALSE(aabbsOverlap(empty, box));
  EXPECT_FALSE(aabbsOverlap(box, empty, 1e9));
}

}  // namespace
}  // namespace polydem::broadphase
