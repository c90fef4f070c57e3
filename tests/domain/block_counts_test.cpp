// chooseBlockCounts: enough blocks, roughly cubic, scale-free, minimum block edge.
#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "polydem/domain/block_forest.h"
#include "polydem/domain/domain_error.h"

namespace polydem::domain {
namespace {

// The counts must not depend on the length unit.
const double kScales[] = {1e-3, 1.0, 1e3};

double maxEdge(const Aabb& d, const Index3& n) {
  return std::max({d.extent().x() / n[0], d.extent().y() / n[1], d.extent().z() / n[2]});
}

TEST(ChooseBlockCounts, Properties) {
  const Vec3 shapes[] = {Vec3(1, 1, 1), Vec3(10, 1, 1), Vec3(100, 100, 1), Vec3(3, 2, 7)};
  for (const Vec3& shape : shapes) {
    for (int ranks : {1, 2, 3, 4, 7, 16, 64}) {
      for (int hint : {1, 4, 8}) {
        Index3 reference{0, 0, 0};
        for (double s : kScales) {
          const Aabb d(s * Vec3(-0.5, 2, 1), s * (Vec3(-0.5, 2, 1) + shape));
          const Index3 n = chooseBlockCounts(d, ranks, hint);
          if (s == kScales[0]) reference = n;
          EXPECT_EQ(n, reference) << "counts depend on the length scale";
          const long total = static_cast<long>(n[0]) * n[1] * n[2];
          EXPECT_GE(total, static_cast<long>(ranks) * hint);
          // the last split at most doubled the count
          EXPECT_LT(total, 2L * ranks * hint);
          // roughly cubic: every split axis has edges at least half the longest edge
          for (int a = 0; a < 3; ++a) {
            if (n[a] > 1) {
              EXPECT_GE(d.extent()[a] / n[a], 0.5 * maxEdge(d, n) * (1 - 1e-12));
            }
          }
        }
      }
    }
  }
  // a cube with a cube number of blocks gets equal counts
  EXPECT_EQ(chooseBlockCounts(Aabb(Vec3::Zero(), Vec3::Ones()), 64, 8), (Index3{8, 8, 8}));
  EXPECT_EQ(chooseBlockCounts(Aabb(Vec3::Zero(), Vec3(2, 1, 1)), 1, 2), (Index3{2, 1, 1}));
}

TEST(ChooseBlockCounts, MinimumBlockEdge) {
  const Aabb d(Vec3::Zero(), Vec3(4, 2, 1));
  const Index3 n = chooseBlockCounts(d, 4, 8, 0.5);
  EXPECT_GE(d.extent().x() / n[0], 0.5);
  EXPECT_GE(d.extent().y() / n[1], 0.5);
  EXPECT_GE(d.extent().z() / n[2], 0.5);
  EXPECT_GE(n[0] * n[1] * n[2], 32);
  EXPECT_EQ(chooseBlockCounts(d, 4, 8, 1.0), (Index3{4, 2, 1}));  // capped below 32
  EXPECT_THROW(chooseBlockCounts(d, 9, 1, 1.0), DomainError);     // 8 blocks for 9 ranks
  EXPECT_THROW(chooseBlockCounts(d, 0, 1), DomainError);
  EXPECT_THROW(chooseBlockCounts(d, 2, 0), DomainError);
}

}  // namespace
}  // namespace polydem::domain
