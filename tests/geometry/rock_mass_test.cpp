// Rock masses cut by joint sets and single planes: the blocks fill the region exactly (volumes
// sum to the region's, every sample point lies in exactly one block), slivers are merged or
// dropped, fixed and removed sides, determinism and scale-freedom.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "common/rock_mass_util.h"
#include "polydem/core/error.h"
#include "polydem/core/random.h"
#include "polydem/geometry/polygon_partition.h"
#include "polydem/geometry/rock_mass.h"

namespace polydem::geometry {
namespace {

// Every random point of the region lies in exactly one block (up to a thin shell around the
// block faces, where round-off decides).
void expectPartition(const RockMass& m, const RockRegion& region, int samples) {
  Vec3 lo = Vec3::Constant(INFINITY), hi = Vec3::Constant(-INFINITY);
  for (const Vec3& c : region.corners()) {
    lo = lo.cwiseMin(c);
    hi = hi.cwiseMax(c);
  }
  std::vector<ConvexPolyhedron> blocks;
  for (const RockBlock& b : m.blocks) blocks.push_back(ConvexPolyhedron::fromPoints(b.vertices));
  const double shell = 1e-9 * (hi - lo).norm();
  SplitMix64 random(99);
  int inside_region = 0;
  for (int i = 0; i < samples; ++i) {
    Vec3 x;
    for (int d = 0; d < 3; ++d) x[d] = lo[d] + (hi[d] - lo[d]) * random.uniform();
    bool in_region = false;
    for (const auto& p : region.pieces) in_region |= p.contains(x, -shell);
    int strictly = 0, loosely = 0;
    for (const auto& b : blocks) {
      strictly += b.contains(x, -shell);
      loosely += b.contains(x, shell);
    }
    if (in_region) {
      ++inside_region;
      EXPECT_EQ(strictly, 1) << "point " << x.transpose();
    } else {
      EXPECT_EQ(strictly, 0) << "point outside the region in a block: " << x.transpose();
    }
    EXPECT_LE(loosely, 2);  // never inside two blocks, only on a face between two
  }
  EXPECT_GT(inside_region, samples / 10);
}

TEST(NormalFromDip, GeologicalConvention) {
  EXPECT_NEAR((normalFromDip(0, 123) - Vec3::UnitZ()).norm(), 0.0, 1e-15);
  // Dipping 30 deg towards east: the plane through the origin descends along +x.
  const Vec3 n = normalFromDip(30, 90);
  EXPECT_NEAR((n - Vec3(0.5, 0.0, std::sqrt(3.0) / 2.0)).norm(), 0.0, 1e-15);
  // Vertical plane striking east-west, dipping towards north: normal +y.
  EXPECT_NEAR((normalFromDip(90, 0) - Vec3::UnitY()).norm(), 0.0, 1e-15);
}

TEST(RockMass, OrthogonalSetsCutABoxIntoTheirCells) {
  RockMassSpec spec;
  spec.region = boxRegion(Vec3(0, 0, 0), Vec3(4, 3, 2));
  spec.joint_sets = {set("ns", 90, 90, 1.0, 0.5), set("ew", 90, 0, 1.0, 0.5),
                     set("bed", 0, 0, 1.0, 0.5)};
  const RockMass m = cutRockMass(spec);
  // Planes at 0.5, 1.5, ... : 5 x 4 x 3 cells, the outer ones half or quarter blocks.
  EXPECT_EQ(m.blocks.size(), 5u * 4u * 3u);
  EXPECT_NEAR(totalVolume(m), 24.0, 1e-12 * 24.0);
  EXPECT_EQ(m.report.free_blocks, 60);
  EXPECT_EQ(m.report.fixed_blocks, 0);
  EXPECT_EQ(m.report.planes, 4 + 3 + 2);
  expectPartition(m, spec.region, 2000);
}

// The blocks come in the order of a plane-by-plane cut (the part below a plane before the part
// above): after the sets ns (normal +x), ew (+y) and bed (+z), ordered by x, then y, then z.
// Single planes remove their sides from every block they meet, in plane order.
TEST(RockMass, BlocksComeInPlaneByPlaneOrder) {
  RockMassSpec spec;
  spec.region = boxRegion(Vec3(0, 0, 0), Vec3(4, 3, 2));
  spec.joint_sets = {set("ns", 90, 90, 1.0, 0.5), set("ew", 90, 0, 1.0, 0.5),
                     set("bed", 0, 0, 1.0, 0.5)};
  SinglePlane cap{"cap", {Vec3::UnitZ(), 1.75}, Side::kNone, Side::kAbove};
  SinglePlane wall{"wall", {Vec3::UnitX(), 3.25}, Side::kNone, Side::kAbove};
  spec.planes = {cap, wall};
  const RockMass m = cutRockMass(spec);
  ASSERT_EQ(m.blocks.size(), 4u * 4u * 3u);  // the wall leaves the ns plane at x = 3.5 nothing
  for (std::size_t i = 1; i < m.blocks.size(); ++i) {
    const Vec3& a = m.blocks[i - 1].centroid;
    const Vec3& b = m.blocks[i].centroid;
    // Centroids of blocks in one slab agree to round-off (1e-9 of the region's size).
    const auto less = [](double u, double v) { return u < v - 4e-9; };
    const auto same = [&](double u, double v) { return !less(u, v) && !less(v, u); };
    const bool before = less(a.x(), b.x()) || (same(a.x(), b.x()) && less(a.y(), b.y())) ||
                        (same(a.x(), b.x()) && same(a.y(), b.y()) && less(a.z(), b.z()));
    EXPECT_TRUE(before) << "block " << i - 1 << " at " << a.transpose() << ", block " << i << " at "
                        << b.transpose();
  }
  // The cap takes 4 x 3 x 0.25 m^3 in one piece, the wall what is left beyond x = 3.25.
  EXPECT_EQ(m.report.removed_blocks, 2);
  EXPECT_NEAR(m.report.removed_volume, 3.0 + 0.75 * 3.0 * 1.75, 1e-12 * 24.0);
  EXPECT_NEAR(totalVolume(m) + m.report.removed_volume, 24.0, 1e-12 * 24.0);
}

TEST(RockMass, JitteredSetsFillTheRegionAndAreDeterministic) {
  RockMassSpec spec;
  spec.region = polyhedronRegion(
      {{0, 0, 0}, {10, 0, 0}, {0, 8, 0}, {10, 8, 1}, {0, 0, 6}, {10, 0, 5}, {0, 8, 6}, {9, 8, 7}});
  JointSet a = set("J1", 70, 120, 1.5, 0.2);
  a.spacing_jitter = 0.3;
  a.orientation_jitter = 8;
  a.seed = 11;
  JointSet b = set("J2", 55, 250, 2.0);
  b.spacing_jitter = 0.2;
  b.orientation_jitter = 5;
  b.seed = 12;
  JointSet c = set("J3", 15, 30, 1.2);
  c.orientation_jitter = 3;
  c.seed = 13;
  spec.joint_sets = {a, b, c};
  spec.min_volume = 0.01;
  const RockMass m = cutRockMass(spec);
  EXPECT_GT(m.blocks.size(), 100u);
  EXPECT_NEAR(totalVolume(m), spec.region.volume, 1e-11 * spec.region.volume);
  EXPECT_GE(m.report.smallest_volume, spec.min_volume);
  expectPartition(m, spec.region, 1500);
  // The same description gives the same bits.
  const RockMass again = cutRockMass(spec);
  ASSERT_EQ(again.blocks.size(), m.blocks.size());
  for (std::size_t i = 0; i < m.blocks.size(); ++i) {
    ASSERT_EQ(again.blocks[i].vertices.size(), m.blocks[i].vertices.size());
    for (std::size_t k = 0; k < m.blocks[i].vertices.size(); ++k) {
      EXPECT_EQ(again.blocks[i].vertices[k], m.blocks[i].vertices[k]);
    }
  }
}

TEST(JointSetPlanes, JitterOfAPlaneDoesNotDependOnTheRegion) {
  JointSet s = set("J", 60, 45, 1.0, 0.3);
  s.spacing_jitter = 0.4;
  s.orientation_jitter = 10;
  s.seed = 5;
  const auto small = jointSetPlanes(s, {{0, 0, 0}, {3, 3, 3}});
  const auto large = jointSetPlanes(s, {{-20, -20, -20}, {20, 20, 20}});
  ASSERT_FALSE(small.empty());
  EXPECT_GT(large.size(), small.size());
  for (const JointPlane& p : small) {
    bool found = false;
    for (const JointPlane& q : large) {
      if (q.index != p.index) continue;
      found = true;
      EXPECT_EQ(q.plane.normal, p.plane.normal);
      EXPECT_EQ(q.plane.offset, p.plane.offset);
    }
    EXPECT_TRUE(found) << "plane " << p.index;
  }
  // Gaps are within (1 +- jitter) spacing along the set's normal, measured at the origin.
  const Vec3 n0 = normalFromDip(60, 45);
  for (std::size_t i = 1; i < large.size(); ++i) {
    const auto along = [&n0](const JointPlane& p) {
      return p.plane.offset / p.plane.normal.dot(n0);
    };
    const double gap = along(large[i]) - along(large[i - 1]);
    EXPECT_GE(gap, 0.6 - 1e-9);
    EXPECT_LE(gap, 1.4 + 1e-9);
  }
}

TEST(RockMass, SliversAreMergedOrDropped) {
  RockMassSpec spec;
  spec.region = boxRegion(Vec3(0, 0, 0), Vec3(1, 1, 1));
  // Planes at x = 0.001 and x = 1.001: the first would cut off a slice of 0.001 m^3.
  spec.joint_sets = {set("x", 90, 90, 1.0, 0.001)};
  spec.min_volume = 0.01;
  const RockMass merged = cutRockMass(spec);
  ASSERT_EQ(merged.blocks.size(), 1u);
  EXPECT_NEAR(merged.blocks[0].volume, 1.0, 1e-14);
  EXPECT_EQ(merged.report.slivers_merged, 1);
  ASSERT_EQ(merged.blocks[0].sides.size(), 1u);  // the joint ends at this block
  EXPECT_EQ(merged.blocks[0].sides[0].plane, 0);
  EXPECT_EQ(merged.blocks[0].sides[0].side, 0);

  spec.slivers = Slivers::kDrop;
  const RockMass dropped = cutRockMass(spec);
  ASSERT_EQ(dropped.blocks.size(), 1u);
  EXPECT_NEAR(dropped.blocks[0].volume, 0.999, 1e-12);
  EXPECT_EQ(dropped.report.slivers_dropped, 1);
  EXPECT_NEAR(dropped.report.dropped_volume, 0.001, 1e-12);
  EXPECT_NEAR(totalVolume(dropped) + dropped.report.dropped_volume, 1.0, 1e-14);

  spec.min_volume = 0.0005;  // now the slice is a block
  EXPECT_EQ(cutRockMass(spec).blocks.size(), 2u);
}

TEST(RockMass, FaultsFixAndRemoveSides) {
  RockMassSpec spec;
  spec.region = boxRegion(Vec3(0, 0, 0), Vec3(10, 4, 6));
  SinglePlane base;
  base.name = "base";
  base.plane.normal = normalFromDip(25, 90);
  base.plane.offset = base.plane.normal.dot(Vec3(5, 0, 2));
  base.fixed = Side::kBelow;
  SinglePlane cut;
  cut.name = "excavation";
  cut.plane.normal = normalFromDip(0, 0);
  cut.plane.offset = 5.0;
  cut.remove = Side::kAbove;
  spec.planes = {base, cut};
  spec.joint_sets = {set("J", 90, 90, 1.0, 0.5)};
  const RockMass m = cutRockMass(spec);
  EXPECT_NEAR(totalVolume(m) + m.report.removed_volume, 240.0, 1e-12 * 240.0);
  EXPECT_NEAR(m.report.removed_volume, 40.0, 1e-12 * 40.0);
  int fixed = 0;
  for (const RockBlock& b : m.blocks) {
    const double s = base.plane.signedDistance(b.centroid);
    EXPECT_EQ(b.fixed, s < 0) << b.centroid.transpose();
    EXPECT_LE(b.centroid.z(), 5.0);
    fixed += b.fixed;
  }
  // The joints cut only the free mass: below the base there is one fixed block.
  EXPECT_EQ(fixed, 1);
  EXPECT_EQ(m.report.fixed_blocks, 1);
  spec.joints_cut_fixed = true;
  EXPECT_GT(cutRockMass(spec).report.fixed_blocks, 1);
}

TEST(RockMass, NonConvexProfileIsCutOnlyByItsJoints) {
  // A 10 x 10 m profile with a V notch in its top, extruded 3 m; unit joints in x and z.
  const std::vector<Vec2> profile = {{0, 0}, {10, 0}, {10, 10}, {6, 10}, {5, 9}, {4, 10}, {0, 10}};
  RockMassSpec spec;
  spec.region = profileRegion(profile, 0.0, 3.0);
  EXPECT_GT(spec.region.pieces.size(), 1u);
  EXPECT_NEAR(spec.region.volume, (100.0 - 1.0) * 3.0, 1e-12 * 300.0);
  spec.joint_sets = {set("x", 90, 90, 1.0), set("z", 0, 0, 1.0)};
  const RockMass m = cutRockMass(spec);
  // Every cell of the joints is convex inside the profile, so no cut other than the joints
  // remains: 10 x 10 cells, those under the notch trimmed.
  EXPECT_EQ(m.blocks.size(), 100u);
  EXPECT_NEAR(totalVolume(m), spec.region.volume, 1e-12 * spec.region.volume);
  expectPartition(m, spec.region, 2000);
  // Without joints the profile needs two blocks (it is not convex), not its triangulation.
  spec.joint_sets.clear();
  EXPECT_EQ(cutRockMass(spec).blocks.size(), 2u);
}

TEST(RockMass, SameBlocksInMillimetresAndMetres) {
  for (double scale : {1e-3, 1e3}) {
    RockMassSpec a, b;
    a.region = boxRegion(Vec3(0, 0, 0), Vec3(5, 4, 3));
    b.region = boxRegion(Vec3(0, 0, 0), scale * Vec3(5, 4, 3));
    JointSet s = set("J", 65, 200, 0.9, 0.1);
    s.spacing_jitter = 0.2;
    s.orientation_jitter = 6;
    s.seed = 3;
    a.joint_sets = {s, set("K", 20, 80, 1.1)};
    s.spacing *= scale;
    s.offset *= scale;
    JointSet k = set("K", 20, 80, 1.1 * scale);
    b.joint_sets = {s, k};
    a.min_volume = 0.02;
    b.min_volume = 0.02 * scale * scale * scale;
    const RockMass ma = cutRockMass(a), mb = cutRockMass(b);
    ASSERT_EQ(ma.blocks.size(), mb.blocks.size()) << "scale " << scale;
    for (std::size_t i = 0; i < ma.blocks.size(); ++i) {
      EXPECT_NEAR(mb.blocks[i].volume, ma.blocks[i].volume * scale * scale * scale,
                  1e-9 * ma.blocks[i].volume * scale * scale * scale);
    }
  }
}

TEST(RockMass, InvalidDescriptionsNameTheSet) {
  RockMassSpec spec;
  spec.region = boxRegion(Vec3(0, 0, 0), Vec3(1, 1, 1));
  spec.joint_sets = {set("bad-set", 40, 0, -1.0)};
  try {
    cutRockMass(spec);
    FAIL() << "no error for a negative spacing";
  } catch (const GeometryError& e) {
    EXPECT_NE(std::string(e.what()).find("bad-set"), std::string::npos) << e.what();
  }
  EXPECT_THROW(profileRegion({{0, 0}, {1, 1}, {1, 0}, {0, 1}}, 0, 1), GeometryError);  // crossing
  EXPECT_THROW(profileRegion({{0, 0}, {1, 0}, {1, 1}}, 1, 1), GeometryError);          // no width
}

TEST(ConvexPartition, PiecesAreConvexAndCoverThePolygon) {
  const std::vector<Vec2> slope = {{0, 0}, {30, 0}, {30, 20}, {18, 20}, {8, 5}, {0, 5}};
  const auto pieces = convexPartition(slope);
  EXPECT_EQ(pieces.size(), 2u);  // one reflex corner, the toe: two pieces
  double area = 0.0;
  for (const auto& p : pieces) {
    const double a = twiceSignedArea(p);
    EXPECT_GT(a, 0.0);
    area += a;
    for (std::size_t i = 0; i < p.size(); ++i) {
      const Vec2 e0 = p[(i + 1) % p.size()] - p[i],
                 e1 = p[(i + 2) % p.size()] - p[(i + 1) % p.size()];
      EXPECT_GE(e0.x() * e1.y() - e0.y() * e1.x(), -1e-9);
    }
  }
  EXPECT_NEAR(area, twiceSignedArea(slope), 1e-12 * area);
}

}  // namespace
}  // namespace polydem::geometry
