// Rock masses within limits: a description beyond them is refused from an estimate before any
// cutting (with the numbers), each block keeps only the planes that bound it, slivers never
// leave a void, a long cut reports progress and stops on a signal.
#include <gtest/gtest.h>

#include <csignal>

#include "common/allocation_counter.h"
#include "common/rock_mass_util.h"
#include "polydem/core/error.h"
#include "polydem/core/interrupt.h"
#include "polydem/geometry/rock_mass.h"

namespace polydem::geometry {
namespace {

std::string errorOf(const RockMassSpec& spec) {
  try {
    cutRockMass(spec);
  } catch (const GeometryError& e) {
    return e.what();
  }
  return "";
}

bool has(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

// The reproducer: two joint sets 8 mm apart in a 30 m box (1.4e7 blocks) ran for
// minutes and died of bad_alloc. Now refused from the estimate, allocating next to nothing.
TEST(RockMassLimits, TooManyBlocksRefusedBeforeCutting) {
  RockMassSpec spec;
  spec.region = boxRegion(Vec3(0, 0, 0), Vec3(30, 30, 30));
  spec.joint_sets = {set("J1", 60, 90, 0.008), set("J2", 60, 270, 0.008)};
  const RockMassEstimate e = estimateRockMass(spec);
  EXPECT_GT(e.blocks, kMaxRockBlocks);
  const long long before = polydem::testing::allocatedBytes();
  const std::string error = errorOf(spec);
  const long long allocated = polydem::testing::allocatedBytes() - before;
  EXPECT_TRUE(has(error, "blocks")) << error;
  EXPECT_TRUE(has(error, "'J1'") && has(error, "'J2'")) << error;
  EXPECT_TRUE(has(error, "0.008 m")) << error;
  EXPECT_TRUE(has(error, "increase the joint sets' spacings")) << error;
  // One block of the cut is a few kB: the refusal made none (the message and the region's
  // corners are all it allocated).
  EXPECT_LT(allocated, 64LL << 10) << allocated << " bytes";
}

// The estimate of the block count against the blocks a cut gives: (1 + m)^3 for three
// orthogonal sets in a box, and close for oblique ones.
TEST(RockMassLimits, EstimateFollowsTheCut) {
  RockMassSpec spec;
  spec.region = boxRegion(Vec3(0, 0, 0), Vec3(4, 3, 2));
  spec.joint_sets = {set("ns", 90, 90, 1.0, 0.5), set("ew", 90, 0, 1.0, 0.5),
                     set("bed", 0, 0, 1.0, 0.5)};
  EXPECT_NEAR(estimateRockMass(spec).blocks, 5.0 * 4.0 * 3.0, 1e-9);
  spec.region = boxRegion(Vec3(0, 0, 0), Vec3(10, 10, 10));
  spec.joint_sets = {set("A", 60, 30, 1.3), set("B", 45, 200, 1.7), set("C", 20, 120, 2.1)};
  const double estimate = estimateRockMass(spec).blocks;
  const double blocks = static_cast<double>(cutRockMass(spec).blocks.size());
  EXPECT_GT(estimate, 0.5 * blocks) << estimate << " for " << blocks;
  EXPECT_LT(estimate, 2.0 * blocks) << estimate << " for " << blocks;
}

// A spacing of 1 um across 30 m: the message names the spacing and the count, not the origin.
TEST(RockMassLimits, TinySpacingBlamesTheSpacing) {
  RockMassSpec spec;
  spec.region = boxRegion(Vec3(0, 0, 0), Vec3(30, 30, 30));
  spec.joint_sets = {set("fine", 0, 0, 1e-6)};
  const std::string error = errorOf(spec);
  EXPECT_TRUE(has(error, "joint set 'fine': spacing 1e-06 m")) << error;
  EXPECT_TRUE(has(error, "planes across the region")) << error;
  EXPECT_FALSE(has(error, "origin")) << error;
  // A region far from plane 0 is still blamed on the origin.
  spec.joint_sets = {set("far", 0, 0, 1.0, -5e7)};
  EXPECT_TRUE(has(errorOf(spec), "put origin (or offset) near the region")) << errorOf(spec);
}

// Spacing jitter close to 1 gives about as many planes as without (the gaps average the
// spacing): accepted, not refused as "1.28e7 planes".
TEST(RockMassLimits, SpacingJitterIsNotMistakenForManyPlanes) {
  RockMassSpec spec;
  spec.region = boxRegion(Vec3(0, 0, 0), Vec3(17, 4, 4));
  JointSet s = set("J", 90, 90, 1.0);
  s.spacing_jitter = 0.9999999;
  s.seed = 5;
  spec.joint_sets = {s};
  spec.min_volume = 0.5;
  const RockMass m = cutRockMass(spec);
  EXPECT_GT(m.planes.size(), 5u);
  EXPECT_LT(m.planes.size(), 60u);
  EXPECT_NEAR(totalVolume(m), 17.0 * 16.0, 1e-9 * 17.0 * 16.0);
}

// Each block lists only the planes a face of it lies on, a few however many planes cut the mass;
// it lies wholly on one side of every other plane.
TEST(RockMassLimits, BlocksKeepOnlyTheirBoundingPlanes) {
  RockMassSpec spec;
  spec.region = boxRegion(Vec3(0, 0, 0), Vec3(25, 6, 5));
  spec.joint_sets = {set("x", 90, 90, 0.25, 0.1), set("z", 0, 0, 1.0, 0.5), set("o", 50, 30, 2.0)};
  const RockMass m = cutRockMass(spec);
  ASSERT_GT(m.planes.size(), 100u);
  for (const RockBlock& b : m.blocks) {
    EXPECT_LE(b.sides.size(), 8u);  // a cell of three sets has at most 6 faces on them
    EXPECT_GE(b.sides.size(), 1u);
    std::vector<bool> listed(m.planes.size(), false);
    for (std::size_t i = 0; i < b.sides.size(); ++i) {
      const PlaneSide& s = b.sides[i];
      if (i > 0) {
        EXPECT_GT(s.plane, b.sides[i - 1].plane);  // in the order applied
      }
      listed[static_cast<std::size_t>(s.plane)] = true;
      const Plane& plane = m.planes[static_cast<std::size_t>(s.plane)];
      int on = 0;
      for (const Vec3& v : b.vertices) on += std::abs(plane.signedDistance(v)) < 1e-9;
      EXPECT_GE(on, 3) << m.plane_names[static_cast<std::size_t>(s.plane)];
      EXPECT_EQ(sideOf(b.vertices, plane), s.side);
    }
    for (std::size_t k = 0; k < m.planes.size(); ++k) {
      if (!listed[k]) {
        EXPECT_NE(sideOf(b.vertices, m.planes[k]), 0) << m.plane_names[k];
      }
    }
  }
}

// The reproducer: a wedge of a slope profile smaller than min_volume, which no
// neighbour can take in and stay convex, was dropped (a void). Now kept, with its place.
TEST(RockMassLimits, SliverWedgeIsKeptNotDropped) {
  const std::vector<Vec2> profile = {{0, 0},   {40, 0},  {40, 10}, {21, 10},
                                     {20, 15}, {19, 10}, {0, 10}};
  RockMassSpec spec;
  spec.region = profileRegion(profile, 0.0, 5.0);
  spec.min_volume = 30.0;
  const double region = 400.0 * 5.0 + 25.0;
  ASSERT_NEAR(spec.region.volume, region, 1e-9 * region);
  const RockMass m = cutRockMass(spec);
  EXPECT_EQ(m.report.slivers_dropped, 0);
  EXPECT_NEAR(totalVolume(m), region, 1e-9 * region);
  ASSERT_EQ(m.report.kept_slivers.size(), 1u);
  const RockPiece& wedge = m.report.kept_slivers[0];
  EXPECT_NEAR(wedge.volume, 25.0, 1e-9 * 25.0);
  EXPECT_NEAR((wedge.centroid - Vec3(20.0, 2.5, 10.0 + 5.0 / 3.0)).norm(), 0.0, 1e-9 * 40.0);

  // slivers = "drop": the wedge goes, and the report says where.
  spec.slivers = Slivers::kDrop;
  const RockMass d = cutRockMass(spec);
  ASSERT_EQ(d.report.dropped.size(), 1u);
  EXPECT_NEAR(d.report.dropped[0].volume, 25.0, 1e-9 * 25.0);
  EXPECT_NEAR((d.report.dropped[0].centroid - wedge.centroid).norm(), 0.0, 1e-9 * 40.0);
  EXPECT_NEAR(totalVolume(d) + d.report.dropped_volume, region, 1e-9 * region);
}

TEST(RockMassLimits, ProgressIsReported) {
  RockMassSpec spec;
  spec.region = boxRegion(Vec3(0, 0, 0), Vec3(10, 10, 10));
  spec.joint_sets = {set("x", 90, 90, 0.5), set("z", 0, 0, 0.5)};
  spec.progress_seconds = 0.0;  // every poll
  std::vector<CutProgress> seen;
  spec.progress = [&](const CutProgress& p) { seen.push_back(p); };
  const RockMass m = cutRockMass(spec);
  ASSERT_GT(seen.size(), 2u);
  for (std::size_t i = 1; i < seen.size(); ++i) {
    EXPECT_GE(seen[i].planes_done, seen[i - 1].planes_done);
    EXPECT_GE(seen[i].blocks, seen[i - 1].blocks);
    EXPECT_EQ(seen[i].planes, m.planes.size());
  }
  EXPECT_LE(seen.back().blocks, m.blocks.size());
}

int g_signal = 0;
int probe() {
  return g_signal;
}

TEST(RockMassLimits, StopSignalEndsTheCut) {
  RockMassSpec spec;
  spec.region = boxRegion(Vec3(0, 0, 0), Vec3(10, 10, 10));
  spec.joint_sets = {set("x", 90, 90, 0.5), set("z", 0, 0, 0.5)};
  setInterruptProbe(&probe);
  EXPECT_NO_THROW(cutRockMass(spec));  // no signal: nothing happens
  g_signal = SIGTERM;
  try {
    cutRockMass(spec);
    ADD_FAILURE() << "the cut went on after SIGTERM";
  } catch (const Interrupted& e) {
    EXPECT_TRUE(has(e.what(), "stopped by SIGTERM while cutting the rock mass (plane "))
        << e.what();
  }
  setInterruptProbe(nullptr);
  g_signal = 0;
}

}  // namespace
}  // namespace polydem::geometry
