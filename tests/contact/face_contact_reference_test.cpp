// The library's sub-contact builder against the straightforward reference builder
// (face_contact_reference.h, kept verbatim): on many face pairs of boxes and sheared
// parallelepipeds, the same kind, the same sub-contacts (feature keys) in the same order, and
// weights, gaps, points, normals and area equal up to round-off. Tolerance: 1e-12 relative to the
// pair's size (weights 1e-12 absolute: they sum to 1; points 1e-12 of the size plus the distance
// from the origin, whose last bits every position carries).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <random>
#include <vector>

#include "box_face_pairs.h"
#include "contact_test_util.h"
#include "face_contact_reference.h"
#include "polydem/contact/face/face_contact.h"
#include "polydem/contact/support.h"
#include "polydem/geometry/shapes.h"

namespace polydem::contact {
namespace {

using testing::boxShape;
using testing::Placed;

// A parallelepiped with edges e1, e2, e3 (not necessarily orthogonal), centred at the origin.
geometry::ConvexPolyhedron parallelepiped(const Vec3& e1, const Vec3& e2, const Vec3& e3) {
  std::vector<Vec3> corners;
  for (int i = 0; i < 8; ++i) {
    corners.push_back(0.5 *
                      ((i & 1 ? 1 : -1) * e1 + (i & 2 ? 1 : -1) * e2 + (i & 4 ? 1 : -1) * e3));
  }
  return geometry::ConvexPolyhedron::fromPoints(corners);
}

struct Tally {
  int pairs = 0, faces = 0, lines = 0, points = 0;
};

// Builds the pair's sub-contacts with both builders and compares them. `size` is the pair's
// length scale, `reach` the largest distance of the pair from the origin.
void expectSame(const Body& a, const Body& b, const Contact& c, double size, double reach,
                FaceContactBuilder& now, reference::ReferenceFaceContactBuilder& before,
                Tally& tally) {
  const FaceContact got = now.build(a, b, c);
  const FaceContact ref = before.build(a, b, c);
  ++tally.pairs;
  ASSERT_EQ(got.kind, ref.kind) << "pair " << tally.pairs;
  tally.faces += got.kind == ContactArea::kFace;
  tally.lines += got.kind == ContactArea::kLine;
  tally.points += got.kind == ContactArea::kPoint;
  ASSERT_EQ(got.subs.size(), ref.subs.size()) << "pair " << tally.pairs;
  const double tol = 1e-12 * size;
  EXPECT_NEAR(got.area, ref.area, 1e-12 * size * size) << "pair " << tally.pairs;
  for (std::size_t i = 0; i < ref.subs.size(); ++i) {
    const SubContact &g = got.subs[i], &r = ref.subs[i];
    ASSERT_EQ(g.feature, r.feature) << "pair " << tally.pairs << " corner " << i;
    EXPECT_NEAR(g.weight, r.weight, 1e-12) << "pair " << tally.pairs;
    EXPECT_NEAR(g.gap, r.gap, tol) << "pair " << tally.pairs;
    EXPECT_LE((g.point - r.point).norm(), tol + 1e-12 * reach) << "pair " << tally.pairs;
    EXPECT_LE((g.normal - r.normal).norm(), 1e-12) << "pair " << tally.pairs;
  }
}

// Face `ia` of `sa` on face `ib` of `sb`, placed as testing::placeFaceOnFace says, both builders
// compared.
void faceOnFace(const geometry::ConvexPolyhedron& sa, const geometry::ConvexPolyhedron& sb, int ia,
                int ib, double spin, const Vec3& tilt_axis, double tilt, const Vec2& slide,
                double depth, double scale, const Mat3& turn, const Vec3& shift,
                FaceContactBuilder& now, reference::ReferenceFaceContactBuilder& before,
                Tally& tally) {
  testing::placeFaceOnFace(
      sa, sb, ia, ib, spin, tilt_axis, tilt, slide, depth, scale, turn, shift,
      [&](const Placed& a, const Placed& b, const Contact& c, double size, double reach) {
        expectSame(a.body(), b.body(), c, size, reach, now, before, tally);
      });
}

// Random boxes and sheared parallelepipeds (1e-3 to 1e3 m, up to 1,000 sizes from the origin)
// face to face: turned at random or aligned, tilted within the facing angle (up to 19 degrees) and
// beyond it (21 to 40 degrees: edge-face or one point), slid from full to partial overlaps and
// corners barely touching.
TEST(FaceContactReference, RandomBoxesAndParallelepipedsGiveTheSameSubContacts) {
  std::mt19937_64 rng(151);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  FaceContactBuilder now(false);  // the general path, which the reference is
  reference::ReferenceFaceContactBuilder before;
  Tally tally;
  for (int trial = 0; trial < 6000; ++trial) {
    auto shape = [&](bool sheared) {
      const Vec3 half(0.5 + 0.4 * u(rng), 0.5 + 0.4 * u(rng), 0.5 + 0.4 * u(rng));
      if (!sheared) return boxShape(half);
      return parallelepiped(Vec3(2 * half.x(), 0.3 * u(rng), 0.3 * u(rng)),
                            Vec3(0.3 * u(rng), 2 * half.y(), 0.3 * u(rng)),
                            Vec3(0.3 * u(rng), 0.3 * u(rng), 2 * half.z()));
    };
    const auto sa = shape(trial % 4 == 3), sb = shape(trial % 3 == 2);
    const int ia = static_cast<int>(rng() % sa.faces().size());
    const int ib = static_cast<int>(rng() % sb.faces().size());
    const double spin = trial % 5 == 0 ? 0.0 : std::numbers::pi * u(rng);
    const double tilt = testing::randomTilt(trial, rng);
    const double reach = 1.2 * (std::sqrt(sa.faces()[ia].area) + std::sqrt(sb.faces()[ib].area));
    const Vec2 slide = (trial % 7 == 0 ? 0.05 : 0.5) * reach * Vec2(u(rng), u(rng));
    const testing::PairMotion m = testing::randomPairMotion(trial, rng);
    faceOnFace(sa, sb, ia, ib, spin, Vec3(u(rng), u(rng), 0.0), tilt, slide, m.depth, m.scale,
               m.turn, m.shift, now, before, tally);
    if (::testing::Test::HasFatalFailure()) return;
  }
  std::printf("pairs %d: face %d, line %d, point %d\n", tally.pairs, tally.faces, tally.lines,
              tally.points);
  EXPECT_EQ(tally.pairs, 6000);
  EXPECT_GT(tally.faces, 2000);
  EXPECT_GT(tally.lines, 100);
  EXPECT_GT(tally.points, 100);
}

// Aligned boxes whose faces' corners lie exactly on the other face's edge lines, as in a dense pack
// of equal cubes: equal squares on top of each other, shifted by exact binary fractions of their
// side along one or both edges, and boxes of different sizes sharing an edge line. The clip meets
// corners with zero or round-off-sized distances to its lines; the labels must still agree.
TEST(FaceContactReference, DegenerateClipsGiveTheSameSubContacts) {
  std::mt19937_64 rng(152);
  FaceContactBuilder now(false);  // the general path, which the reference is
  reference::ReferenceFaceContactBuilder before;
  Tally tally;
  testing::forEachDegenerateBoxFacePair(
      rng, [&](const Body& a, const Body& b, const Contact& c, double size, double reach) {
        expectSame(a, b, c, size, reach, now, before, tally);
        return !::testing::Test::HasFatalFailure();
      });
  std::printf("pairs %d: face %d, line %d, point %d\n", tally.pairs, tally.faces, tally.lines,
              tally.points);
  EXPECT_GT(tally.faces, 150);
}

}  // namespace
}  // namespace polydem::contact
