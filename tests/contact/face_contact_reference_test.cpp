// The library's sub-contact builder against the builder before issue 15's cheaper one
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

#include "contact_test_util.h"
#include "face_contact_reference.h"
#include "polydem/contact/face_contact.h"
#include "polydem/contact/support.h"
#include "polydem/geometry/shapes.h"

namespace polydem::contact {
namespace {

using testing::Placed;

Mat3 about(const Vec3& axis, double angle) {
  return Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix();
}

geometry::ConvexPolyhedron boxShape(const Vec3& half) {
  return geometry::ConvexPolyhedron::fromPoints(geometry::shapes::boxAround(Vec3::Zero(), half));
}

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

// A random face of A turned onto a random face of B (B's face at z = 0 looking up, A's looking
// down), A turned about z, tilted about a horizontal axis by `tilt`, slid in the plane and sunk by
// `depth`; then the whole pair scaled by `scale`, turned by `turn` and moved by `shift`. The
// contact normal is B's face normal (+z before the motion), the point the slide.
void faceOnFace(const geometry::ConvexPolyhedron& sa, const geometry::ConvexPolyhedron& sb, int ia,
                int ib, double spin, const Vec3& tilt_axis, double tilt, const Vec2& slide,
                double depth, double scale, const Mat3& turn, const Vec3& shift,
                FaceContactBuilder& now, reference::ReferenceFaceContactBuilder& before,
                Tally& tally) {
  const auto& fa = sa.faces()[ia];
  const auto& fb = sb.faces()[ib];
  const Mat3 rb = Eigen::Quaterniond::FromTwoVectors(fb.normal, Vec3::UnitZ()).toRotationMatrix();
  const Mat3 ra = about(tilt_axis, tilt) * about(Vec3::UnitZ(), spin) *
                  Eigen::Quaterniond::FromTwoVectors(fa.normal, -Vec3::UnitZ()).toRotationMatrix();
  const Vec3 point(slide.x(), slide.y(), 0.0);
  const Vec3 xa = point - ra * fa.centroid - depth * Vec3::UnitZ();
  const Vec3 xb = -(rb * fb.centroid);
  Placed a(geometry::ConvexPolyhedron(sa), shift + scale * (turn * xa), turn * ra);
  Placed b(geometry::ConvexPolyhedron(sb), shift + scale * (turn * xb), turn * rb);
  Contact c;
  c.touching = true;
  c.normal = turn * Vec3::UnitZ();
  c.point = shift + scale * (turn * point);
  c.depth = scale * depth;
  const double size = pairLengthScale(a.body(), b.body());
  expectSame(a.body(), b.body(), c, size, shift.norm() + 4.0 * size, now, before, tally);
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
  const double deg = std::numbers::pi / 180.0;
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
    double tilt = 0.0;
    switch (trial % 6) {
      case 0:
        tilt = 0.0;
        break;
      case 1:
        tilt = 1e-9 * u(rng);
        break;
      case 2:
        tilt = 1e-4 * u(rng);
        break;
      case 3:
        tilt = 19.0 * deg * u(rng);
        break;
      case 4:
        tilt = (21.0 + 19.0 * (0.5 + 0.5 * u(rng))) * deg;
        break;
      default:
        tilt = 5.0 * deg * u(rng);
        break;
    }
    const double reach = 1.2 * (std::sqrt(sa.faces()[ia].area) + std::sqrt(sb.faces()[ib].area));
    const Vec2 slide = (trial % 7 == 0 ? 0.05 : 0.5) * reach * Vec2(u(rng), u(rng));
    const double depth = std::pow(10.0, -3.0 - 6.0 * (0.5 + 0.5 * u(rng)));
    const double scale = std::pow(10.0, 3.0 * u(rng));
    const Mat3 turn = trial % 2 == 0 ? Mat3::Identity() : testing::randomRotation(rng);
    const Vec3 shift = scale * 1000.0 * (0.5 + 0.5 * u(rng)) * testing::randomUnit(rng);
    faceOnFace(sa, sb, ia, ib, spin, Vec3(u(rng), u(rng), 0.0), tilt, slide, depth, scale, turn,
               shift, now, before, tally);
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
  const double shifts[] = {0.0, 0.25, 0.5, -0.5, 0.125, 1e-3, -1e-3, 1e-12};
  for (const Vec3& half_a : {Vec3(0.5, 0.5, 0.5), Vec3(0.25, 0.5, 0.5), Vec3(0.5, 0.375, 0.5)}) {
    for (double sx : shifts) {
      for (double sy : shifts) {
        for (int motion = 0; motion < 4; ++motion) {
          const double scale = motion == 0 ? 1.0 : std::pow(10.0, -3.0 + 2.0 * motion);
          const Mat3 turn = motion < 2 ? Mat3::Identity() : testing::randomRotation(rng);
          const Vec3 shift =
              motion == 3 ? Vec3(500.0 * scale * testing::randomUnit(rng)) : Vec3::Zero();
          const Vec3 xa(sx, sy, 1.0 - 1e-3 - (0.5 - half_a.z()));
          Placed a(boxShape(scale * half_a), shift + scale * (turn * xa), turn);
          Placed b(boxShape(scale * Vec3(0.5, 0.5, 0.5)), shift, turn);
          Contact c;
          c.touching = true;
          c.normal = turn * Vec3::UnitZ();
          c.point = shift + scale * (turn * Vec3(0.5 * sx, 0.5 * sy, 0.5));
          c.depth = scale * 1e-3;
          const double size = pairLengthScale(a.body(), b.body());
          expectSame(a.body(), b.body(), c, size, shift.norm() + 2.0 * size, now, before, tally);
          if (::testing::Test::HasFatalFailure()) return;
        }
      }
    }
  }
  std::printf("pairs %d: face %d, line %d, point %d\n", tally.pairs, tally.faces, tally.lines,
              tally.points);
  EXPECT_GT(tally.faces, 150);
}

}  // namespace
}  // namespace polydem::contact
