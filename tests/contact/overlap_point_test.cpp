// The overlap-centroid contact point (contact/point/overlap_point.h): volume and centroid of A ∩ B
// against boxes whose intersection is known, and the centre of pressure of a tilted block on a
// plane against the linear-bed answer, at scales 1e-3, 1 and 1e3.
#include "polydem/contact/point/overlap_point.h"

#include <gtest/gtest.h>

#include <cmath>
#include <memory>

#include "contact_test_util.h"
#include "polydem/geometry/shapes.h"

namespace polydem::contact {
namespace {

using testing::Placed;

constexpr double kScales[] = {1e-3, 1.0, 1e3};

std::unique_ptr<Placed> placedBox(const Vec3& lo, const Vec3& hi, const Mat3& r = Mat3::Identity(),
                                  const Vec3& t = Vec3::Zero()) {
  return std::make_unique<Placed>(
      geometry::ConvexPolyhedron::fromPoints(geometry::shapes::box(lo, hi)), t, r);
}

TEST(OverlapCentroid, IntersectionOfTwoBoxesIsTheirCommonBox) {
  const Mat3 r = Quat(Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized())).toRotationMatrix();
  const Vec3 t(0.4, -1.1, 2.3);
  for (double s : kScales) {
    SCOPED_TRACE(s);
    auto a = placedBox(Vec3(0, 0, 0) * s, Vec3(1, 1, 1) * s, r, t * s);
    auto b = placedBox(Vec3(0.3, -0.2, 0.5) * s, Vec3(1.7, 0.6, 2.0) * s, r, t * s);
    OverlapCentroid oc;
    // The apex (any point; here one outside the overlap) only changes the rounding.
    const OverlapVolume v = oc.intersect(a->body(), b->body(), t * s);
    ASSERT_TRUE(v.found);
    EXPECT_NEAR(v.volume, 0.7 * 0.6 * 0.5 * s * s * s, 1e-12 * s * s * s);
    const Vec3 expected = t * s + r * (Vec3(0.65, 0.3, 0.75) * s);
    EXPECT_LT((v.centroid - expected).norm(), 1e-12 * s);
  }
}

TEST(OverlapCentroid, FlushFacesWithTheSameNormalCountOnce) {
  // The block sits in the base's corner: its faces x = 1 and y = 1 lie in the base's side faces.
  for (double s : kScales) {
    SCOPED_TRACE(s);
    const double d = 0.01;
    auto a = placedBox(Vec3(0, 0, -d) * s, Vec3(1, 1, 1 - d) * s);
    auto b = placedBox(Vec3(-4, -4, -2) * s, Vec3(1, 1, 0) * s);
    OverlapCentroid oc;
    const OverlapVolume v = oc.intersect(a->body(), b->body(), Vec3(0.5, 0.5, -0.5 * d) * s);
    ASSERT_TRUE(v.found);
    EXPECT_NEAR(v.volume, d * s * s * s, 1e-12 * s * s * s);
    EXPECT_LT((v.centroid - Vec3(0.5, 0.5, -0.5 * d) * s).norm(), 1e-12 * s);
  }
}

TEST(OverlapCentroid, TouchingFacesHaveNoVolume) {
  auto a = placedBox(Vec3(0, 0, 0), Vec3(1, 1, 1));
  auto b = placedBox(Vec3(-3, -3, -1), Vec3(3, 3, 0));
  OverlapCentroid oc;
  EXPECT_FALSE(oc.intersect(a->body(), b->body(), Vec3(0.5, 0.5, 0)).found);
  Contact touching;
  touching.touching = true;
  touching.point = Vec3(0.5, 0.5, 0);
  EXPECT_EQ(oc.apply(a->body(), b->body(), touching).point, touching.point);
}

// A cube of edge s tilted by alpha about y, its bottom face centre at depth d below the top face
// z = 0 of a large base, the whole bottom face below z = 0 (d > s sin(alpha) / 2). The overlap is
// a prism along y whose section in the xz-plane is the quadrilateral between the tilted bottom
// face, the tilted side faces and z = 0; its centroid is the section's (shoelace formula).
struct TiltedBlock {
  double s, alpha, d;
  Vec3 centroid() const {
    const double c = std::cos(alpha), sn = std::sin(alpha);
    // Bottom corners u = -s/2, +s/2 (the +x side is the low side), then up the sides (direction
    // (sin, cos)) to z = 0.
    const Vec2 bm(-0.5 * c * s, -d + 0.5 * sn * s), bp(0.5 * c * s, -d - 0.5 * sn * s);
    const Vec2 tp(bp.x() + sn * (-bp.y()) / c, 0.0), tm(bm.x() + sn * (-bm.y()) / c, 0.0);
    const Vec2 q[4] = {bm, bp, tp, tm};
    double area = 0.0;
    Vec2 moment = Vec2::Zero();
    for (int i = 0; i < 4; ++i) {
      const Vec2& p = q[i];
      const Vec2& n = q[(i + 1) % 4];
      const double cross = p.x() * n.y() - n.x() * p.y();
      area += 0.5 * cross;
      moment += cross * (p + n) / 6.0;
    }
    return Vec3(moment.x() / area, 0.0, moment.y() / area);
  }
};

struct TiltedPair {
  std::unique_ptr<Placed> block, base;
};
TiltedPair placeTilted(const TiltedBlock& t) {
  const Mat3 r = Eigen::AngleAxisd(t.alpha, Vec3::UnitY()).toRotationMatrix();
  const Vec3 position = Vec3(0, 0, -t.d) - r * Vec3(0, 0, -0.5 * t.s);
  TiltedPair p;
  p.block =
      std::make_unique<Placed>(geometry::ConvexPolyhedron::fromPoints(geometry::shapes::boxAround(
                                   Vec3::Zero(), Vec3::Constant(0.5 * t.s))),
                               position, r);
  p.base = placedBox(Vec3(-5, -5, -2) * t.s, Vec3(5, 5, 0) * t.s);
  return p;
}

TEST(OverlapCentroid, TiltedBlockCentreOfPressureMovesToTheLowSide) {
  for (const char* name : {"gjk-epa-ipm", "fcp-ipm"}) {
    const auto kernel = makeKernel(name);
    for (double s : kScales) {
      SCOPED_TRACE(std::string(name) + " scale " + std::to_string(s));
      const TiltedBlock t{s, 1e-3, 2e-3 * s};
      const TiltedPair p = placeTilted(t);
      const Contact k = kernel->collide(p.block->body(), p.base->body(), nullptr);
      ASSERT_TRUE(k.touching);
      OverlapCentroid oc;
      const OverlapVolume v = oc.intersect(p.block->body(), p.base->body(), k.point);
      ASSERT_TRUE(v.found);
      const Vec3 c = t.centroid();
      EXPECT_LT((v.centroid - c).norm(), 1e-9 * s);
      const Contact moved = oc.apply(p.block->body(), p.base->body(), k);
      const Vec3 expected = c + k.normal * k.normal.dot(k.point - c);
      EXPECT_LT((moved.point - expected).norm(), 1e-9 * s);
      EXPECT_EQ(moved.normal, k.normal);
      EXPECT_EQ(moved.depth, k.depth);
      // Linear bed: the penetration d + u sin(alpha) along the face (u in [-s/2, s/2]) has its
      // centroid at u = s^2 sin(alpha) / (12 d), x = u cos(alpha). The tilted sides cut off
      // slivers of relative size alpha d / s, so the two agree to about 1e-5 here.
      const double shift = s * s * std::sin(t.alpha) * std::cos(t.alpha) / (12.0 * t.d);
      EXPECT_NEAR(moved.point.x(), shift, 1e-3 * shift);
      // The kernel's point (centroid of the overlap polygon) stays at the face centre.
      EXPECT_LT(std::abs(k.point.x()), 1e-3 * shift);
    }
  }
}

TEST(OverlapCentroid, UntiltedBlockPointIsTheFaceCentre) {
  for (const char* name : {"gjk-epa-ipm", "fcp-ipm"}) {
    const auto kernel = makeKernel(name);
    for (double s : kScales) {
      SCOPED_TRACE(std::string(name) + " scale " + std::to_string(s));
      const TiltedBlock t{s, 0.0, 2e-3 * s};
      const TiltedPair p = placeTilted(t);
      const Contact k = kernel->collide(p.block->body(), p.base->body(), nullptr);
      ASSERT_TRUE(k.touching);
      OverlapCentroid oc;
      const Contact moved = oc.apply(p.block->body(), p.base->body(), k);
      EXPECT_LT(std::abs(moved.point.x()), 1e-12 * s);
      EXPECT_LT(std::abs(moved.point.y()), 1e-12 * s);
      EXPECT_NEAR(moved.point.z(), k.point.z(), 1e-12 * s);
    }
  }
}

}  // namespace
}  // namespace polydem::contact
