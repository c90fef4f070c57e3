// The sub-contact builder's box-face path (face_contact_box.cpp) against its general path
// (FaceContactBuilder(false)) on face pairs of rectangular boxes: cubes and boxes of other
// proportions, aligned and turned at random, tilted within the facing angle and beyond it, 1e-3 to
// 1e3 m, up to 1,000 sizes from the origin, full, partial and corner-only overlaps, and the
// aligned pack's configurations, where corners lie on the other face's edge lines.
//
// Asserted: the same kind and the same number of sub-contacts. Where the keys agree (every clip
// that is not degenerate: asserted for the random pairs), each sub-contact's weight, gap, point and
// normal agree within the tolerances of Tolerance below; where they do not (a corner on an edge
// line within round-off, labelled as a vertex by one path and as a crossing by the other), every
// sub-contact has one of the other path's at the same point, with the same weight and gap.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <random>
#include <vector>

#include "box_face_pairs.h"
#include "contact_test_util.h"
#include "polydem/contact/face/face_contact.h"
#include "polydem/contact/support.h"
#include "polydem/geometry/shapes.h"

namespace polydem::contact {
namespace {

using testing::boxShape;
using testing::Placed;

// The two paths compute in different frames (B's face plane against the plane normal to n), so
// their results differ by round-off, relative to the pair's size `size`:
//   - gap: 1e-12 size;
//   - point: 1e-12 size plus 1e-12 of its distance from the origin (`reach`);
//   - normal: 1e-12;
//   - weight: 1e-12 of the face's size squared over the overlap area (a share is an area
//     computed from corners known to round-off of the face's size, so a sliver's weights carry
//     that error relative to its small area); area likewise 1e-12 size^2.
struct Tally {
  int pairs = 0, faces = 0, lines = 0, points = 0, degenerate = 0, extra_general_corners = 0;
  double worst_weight = 0.0, worst_gap = 0.0, worst_point = 0.0;  // relative to the tolerance
};

// Builds the pair with both paths and compares them; `reach` is the pair's distance from the
// origin plus its size, `may_degenerate` allows different keys (then matched by position).
void expectSame(const Body& a, const Body& b, const Contact& c, double reach, bool may_degenerate,
                FaceContactBuilder& box, FaceContactBuilder& general, Tally& tally) {
  const FaceContact got = box.build(a, b, c);
  const FaceContact ref = general.build(a, b, c);
  const double size = pairLengthScale(a, b);
  ++tally.pairs;
  ASSERT_EQ(got.kind, ref.kind) << "pair " << tally.pairs;
  tally.faces += got.kind == ContactArea::kFace;
  tally.lines += got.kind == ContactArea::kLine;
  tally.points += got.kind == ContactArea::kPoint;
  EXPECT_NEAR(got.area, ref.area, 1e-12 * size * size) << "pair " << tally.pairs;
  bool same_keys = got.subs.size() == ref.subs.size();
  for (std::size_t i = 0; same_keys && i < ref.subs.size(); ++i) {
    same_keys = got.subs[i].feature == ref.subs[i].feature;
  }
  const double gap_tol = 1e-12 * size, point_tol = 1e-12 * (size + reach);
  const double weight_tol = got.area > 0.0 ? 1e-12 * size * size / got.area : 1e-12;
  if (same_keys) {
    for (std::size_t i = 0; i < got.subs.size(); ++i) {
      const SubContact &g = got.subs[i], &r = ref.subs[i];
      const double dw = std::abs(g.weight - r.weight), dg = std::abs(g.gap - r.gap);
      const double dp = (g.point - r.point).norm();
      EXPECT_LE(dw, weight_tol) << "pair " << tally.pairs << " corner " << i;
      EXPECT_LE(dg, gap_tol) << "pair " << tally.pairs << " corner " << i;
      EXPECT_LE(dp, point_tol) << "pair " << tally.pairs << " corner " << i;
      EXPECT_LE((g.normal - r.normal).norm(), 1e-12) << "pair " << tally.pairs;
      tally.worst_weight = std::max(tally.worst_weight, dw / weight_tol);
      tally.worst_gap = std::max(tally.worst_gap, dg / gap_tol);
      tally.worst_point = std::max(tally.worst_point, dp / point_tol);
    }
    return;
  }
  // A degenerate clip: the same corners (points and gaps), labelled differently.
  ASSERT_TRUE(may_degenerate) << "pair " << tally.pairs << ": the keys differ";
  ASSERT_EQ(got.kind, ContactArea::kFace) << "pair " << tally.pairs;
  ++tally.degenerate;
  const auto nearest = [](const FaceContact& in, const Vec3& x) {
    std::size_t j = 0;
    for (std::size_t k = 1; k < in.subs.size(); ++k) {
      if ((in.subs[k].point - x).norm() < (in.subs[j].point - x).norm()) j = k;
    }
    return in.subs[j];
  };
  for (std::size_t i = 0; i < got.subs.size(); ++i) {
    const SubContact& g = got.subs[i];
    const SubContact r = nearest(ref, g.point);
    EXPECT_LE((g.point - r.point).norm(), point_tol) << "pair " << tally.pairs << " corner " << i;
    EXPECT_LE(std::abs(g.gap - r.gap), gap_tol) << "pair " << tally.pairs << " corner " << i;
    if (got.subs.size() == ref.subs.size()) {
      EXPECT_LE(std::abs(g.weight - r.weight), weight_tol) << "pair " << tally.pairs;
    }
  }
  // The general path's clip may keep, besides those corners, a crossing made by the round-off of a
  // corner on an edge line: a point on a side of the overlap (the areas agree, asserted above),
  // which its weight rule gives a share of the weight, so the weights are then not compared.
  // The box path puts such a corner on the line and keeps the side's two ends.
  for (std::size_t i = 0; i < ref.subs.size(); ++i) {
    const SubContact& r = ref.subs[i];
    if ((nearest(got, r.point).point - r.point).norm() <= point_tol) continue;
    ++tally.extra_general_corners;
    bool on_side = false;
    for (const SubContact& p : got.subs) {
      for (const SubContact& q : got.subs) {
        const Vec3 d = q.point - p.point;
        if (d.squaredNorm() == 0.0) continue;
        const double t = std::clamp((r.point - p.point).dot(d) / d.squaredNorm(), 0.0, 1.0);
        on_side = on_side || (p.point + t * d - r.point).norm() <= point_tol;
      }
    }
    EXPECT_TRUE(on_side) << "pair " << tally.pairs << ": a general corner off the overlap";
  }
}

void print(const char* what, const Tally& t) {
  std::printf(
      "%s: pairs %d (face %d, line %d, point %d), degenerate labels %d (general path's extra "
      "corners on a side %d); same keys, worst difference / tolerance: weight %.2g, gap %.2g, "
      "point %.2g\n",
      what, t.pairs, t.faces, t.lines, t.points, t.degenerate, t.extra_general_corners,
      t.worst_weight, t.worst_gap, t.worst_point);
}

// Face `ia` of `sa` on face `ib` of `sb`, placed as testing::placeFaceOnFace says, both builders
// compared.
void faceOnFace(const geometry::ConvexPolyhedron& sa, const geometry::ConvexPolyhedron& sb, int ia,
                int ib, double spin, const Vec3& tilt_axis, double tilt, const Vec2& slide,
                double depth, double scale, const Mat3& turn, const Vec3& shift,
                FaceContactBuilder& box, FaceContactBuilder& general, Tally& tally) {
  testing::placeFaceOnFace(
      sa, sb, ia, ib, spin, tilt_axis, tilt, slide, depth, scale, turn, shift,
      [&](const Placed& a, const Placed& b, const Contact& c, double, double reach) {
        ASSERT_NE(a.shape().box(), nullptr);
        ASSERT_NE(b.shape().box(), nullptr);
        expectSame(a.body(), b.body(), c, reach, false, box, general, tally);
      });
}

TEST(FaceContactBox, RandomBoxPairsGiveTheGeneralPathsSubContacts) {
  std::mt19937_64 rng(1515);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  FaceContactBuilder box(true), general(false);
  Tally tally;
  for (int trial = 0; trial < 8000; ++trial) {
    // Cubes, and boxes of other proportions (up to 10:1).
    const auto shape = [&](bool cube) {
      if (cube) return boxShape(Vec3(0.5, 0.5, 0.5));
      return boxShape(Vec3(0.5 + 0.45 * u(rng), 0.5 + 0.45 * u(rng), 0.5 + 0.45 * u(rng)));
    };
    const auto sa = shape(trial % 4 == 0), sb = shape(trial % 3 == 0);
    const int ia = static_cast<int>(rng() % sa.faces().size());
    const int ib = static_cast<int>(rng() % sb.faces().size());
    const double spin = trial % 5 == 0 ? 0.0 : std::numbers::pi * u(rng);
    const double tilt = testing::randomTilt(trial, rng);
    // Full overlaps (small slides), partial ones, and corners barely touching (large slides).
    const double reach = 1.2 * (std::sqrt(sa.faces()[ia].area) + std::sqrt(sb.faces()[ib].area));
    const double slide_size = trial % 7 == 0 ? 0.05 : trial % 7 == 1 ? 0.45 : 0.3;
    const Vec2 slide = slide_size * reach * Vec2(u(rng), u(rng));
    const testing::PairMotion m = testing::randomPairMotion(trial, rng);
    faceOnFace(sa, sb, ia, ib, spin, Vec3(u(rng), u(rng), 0.0), tilt, slide, m.depth, m.scale,
               m.turn, m.shift, box, general, tally);
    if (::testing::Test::HasFatalFailure()) return;
  }
  print("random box pairs", tally);
  EXPECT_EQ(tally.pairs, 8000);
  EXPECT_GT(tally.faces, 3000);
  EXPECT_GT(tally.lines, 100);
  EXPECT_GT(tally.points, 100);
  EXPECT_EQ(tally.degenerate, 0);
}

// Aligned boxes whose corners lie exactly on the other face's edge lines: equal squares shifted by
// exact binary fractions of their side, boxes of half or 3/4 the side sharing an edge line, and
// shifts of 1e-3 and 1e-12 of the side; in place, scaled, turned and moved 500 sizes away.
TEST(FaceContactBox, DegenerateClipsGiveTheSameCorners) {
  std::mt19937_64 rng(1516);
  FaceContactBuilder box(true), general(false);
  Tally tally;
  testing::forEachDegenerateBoxFacePair(
      rng, [&](const Body& a, const Body& b, const Contact& c, double, double reach) {
        expectSame(a, b, c, reach, true, box, general, tally);
        return !::testing::Test::HasFatalFailure();
      });
  print("degenerate clips", tally);
  EXPECT_GT(tally.faces, 700);
}

// The dense pack (`bench scaling --shapes cubes --gap -0.001`): a cube and its 26 neighbours, each
// overlapping it by 1e-3 of the side, with the contact of the kernel the pack uses (gjk-epa-ipm:
// face neighbours meet face to face, edge and corner neighbours in a sliver and a small square).
TEST(FaceContactBox, DensePackNeighboursGiveTheSameCorners) {
  std::mt19937_64 rng(1517);
  const auto kernel = makeKernel("gjk-epa-ipm");
  FaceContactBuilder box(true), general(false);
  Tally tally;
  for (int motion = 0; motion < 4; ++motion) {
    const double scale = motion == 0 ? 1.0 : std::pow(10.0, -3.0 + 2.0 * motion);
    const Mat3 turn = motion < 2 ? Mat3::Identity() : testing::randomRotation(rng);
    const Vec3 shift = motion == 3 ? Vec3(500.0 * scale * testing::randomUnit(rng)) : Vec3::Zero();
    const double pitch = scale * (1.0 - 1e-3);
    Placed b(boxShape(scale * Vec3(0.5, 0.5, 0.5)), shift, turn);
    for (int i = -1; i <= 1; ++i) {
      for (int j = -1; j <= 1; ++j) {
        for (int k = -1; k <= 1; ++k) {
          if (i == 0 && j == 0 && k == 0) continue;
          Placed a(boxShape(scale * Vec3(0.5, 0.5, 0.5)),
                   shift + turn * Vec3(pitch * i, pitch * j, pitch * k), turn);
          particles::PairState state;
          const Contact c = kernel->collideForSubContacts(a.body(), b.body(), &state);
          ASSERT_TRUE(c.touching);
          const double size = pairLengthScale(a.body(), b.body());
          expectSame(a.body(), b.body(), c, shift.norm() + 2.0 * size, true, box, general, tally);
          if (::testing::Test::HasFatalFailure()) return;
        }
      }
    }
  }
  print("dense-pack neighbours", tally);
  EXPECT_EQ(tally.faces, 4 * 26);
}

}  // namespace
}  // namespace polydem::contact
