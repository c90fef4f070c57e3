// Face-contact geometry (contact/face/face_contact.h): which corners a face contact is split into,
// their labels, gaps, points and weights, against answers worked out by hand for boxes; then the
// same answers under rigid motions and changes of unit, and the exactness of the corner forces as
// the gradient of the spring energy.
#include "polydem/contact/face/face_contact.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "contact_test_util.h"
#include "polydem/geometry/shapes.h"

namespace polydem::contact {
namespace {

using testing::Placed;

constexpr double kDepth = 1e-4;

geometry::ConvexPolyhedron boxShape(const Vec3& half) {
  return geometry::ConvexPolyhedron::fromPoints(geometry::shapes::boxAround(Vec3::Zero(), half));
}

Mat3 about(const Vec3& axis, double angle) {
  return Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix();
}

// The contact a kernel would report for A resting on B along +z: depth and point given.
Contact along(const Vec3& normal, const Vec3& point, double depth) {
  Contact c;
  c.touching = true;
  c.normal = normal;
  c.point = point;
  c.depth = depth;
  return c;
}

double weightSum(const FaceContact& fc) {
  double w = 0.0;
  for (const auto& s : fc.subs) w += s.weight;
  return w;
}

// A unit cube sinking kDepth into a 10 x 10 plate: the four bottom corners of the cube, each a
// vertex of A inside B's top face, a quarter of the weight, the plate's normal, the full depth.
TEST(FaceContact, CubeOnPlateGivesItsFourCorners) {
  Placed a(boxShape(Vec3(0.5, 0.5, 0.5)), Vec3(0.3, -0.2, 0.5 - kDepth), Mat3::Identity());
  Placed b(boxShape(Vec3(5, 5, 0.5)), Vec3(0, 0, -0.5), Mat3::Identity());
  FaceContactBuilder builder;
  const auto fc =
      builder.build(a.body(), b.body(), along(Vec3::UnitZ(), Vec3(0.3, -0.2, 0), kDepth));
  ASSERT_EQ(fc.kind, ContactArea::kFace);
  ASSERT_EQ(fc.subs.size(), 4u);
  EXPECT_NEAR(fc.area, 1.0, 1e-12);
  for (std::size_t i = 0; i < fc.subs.size(); ++i) {
    const auto& s = fc.subs[i];
    EXPECT_EQ(featureType(static_cast<std::uint32_t>(s.feature >> 32)), FeatureType::kVertex);
    EXPECT_EQ(featureType(static_cast<std::uint32_t>(s.feature)), FeatureType::kFace);
    if (i > 0) {
      EXPECT_LT(fc.subs[i - 1].feature, s.feature) << "sorted, each feature once";
    }
    EXPECT_NEAR(s.weight, 0.25, 1e-14);
    EXPECT_NEAR(s.gap, kDepth, 1e-15);
    EXPECT_NEAR((s.normal - Vec3::UnitZ()).norm(), 0.0, 1e-15);
    EXPECT_NEAR(s.point.z(), -0.5 * kDepth, 1e-15) << "half way between the two surfaces";
    EXPECT_NEAR(std::abs(s.point.x() - 0.3), 0.5, 1e-12);
    EXPECT_NEAR(std::abs(s.point.y() + 0.2), 0.5, 1e-12);
  }
}

// A face contact names the two facing faces (the joint of a rock mass is looked up by them): the
// cube's bottom face and the plate's top face, on the box path and on the general one; a line
// or point contact names none.
TEST(FaceContact, FaceContactNamesTheFacingFaces) {
  Placed a(boxShape(Vec3(0.5, 0.5, 0.5)), Vec3(0.3, -0.2, 0.5 - kDepth), Mat3::Identity());
  Placed b(boxShape(Vec3(5, 5, 0.5)), Vec3(0, 0, -0.5), Mat3::Identity());
  for (const bool box_path : {true, false}) {
    FaceContactBuilder builder(box_path);
    const auto fc =
        builder.build(a.body(), b.body(), along(Vec3::UnitZ(), Vec3(0.3, -0.2, 0), kDepth));
    ASSERT_EQ(fc.kind, ContactArea::kFace);
    ASSERT_GE(fc.face_a, 0);
    ASSERT_GE(fc.face_b, 0);
    EXPECT_NEAR(a.body().faceNormal(fc.face_a).z(), -1.0, 1e-15) << box_path;
    EXPECT_NEAR(b.body().faceNormal(fc.face_b).z(), 1.0, 1e-15) << box_path;
  }
  const Mat3 r = about(Vec3::UnitX(), std::numbers::pi / 4);
  Placed edge(boxShape(Vec3(0.5, 0.5, 0.5)), Vec3(0.2, 0, 0.5 * std::sqrt(2.0) - kDepth), r);
  FaceContactBuilder builder;
  const auto line =
      builder.build(edge.body(), b.body(), along(Vec3::UnitZ(), Vec3(0.2, 0, 0), kDepth));
  ASSERT_EQ(line.kind, ContactArea::kLine);
  EXPECT_EQ(line.face_a, -1);
  EXPECT_EQ(line.face_b, -1);
}

// The same with the plate as A (the lower uid below): the normal from B (the cube) into A is -z,
// and the cube's corners are vertices of B inside A's face, pushed along minus A's face normal.
TEST(FaceContact, PlateAsAGivesBsCornersInAsFace) {
  Placed a(boxShape(Vec3(5, 5, 0.5)), Vec3(0, 0, -0.5), Mat3::Identity());
  Placed b(boxShape(Vec3(0.5, 0.5, 0.5)), Vec3(0, 0, 0.5 - kDepth), Mat3::Identity());
  FaceContactBuilder builder;
  const auto fc = builder.build(a.body(), b.body(), along(-Vec3::UnitZ(), Vec3::Zero(), kDepth));
  ASSERT_EQ(fc.kind, ContactArea::kFace);
  ASSERT_EQ(fc.subs.size(), 4u);
  for (const auto& s : fc.subs) {
    EXPECT_EQ(featureType(static_cast<std::uint32_t>(s.feature >> 32)), FeatureType::kFace);
    EXPECT_EQ(featureType(static_cast<std::uint32_t>(s.feature)), FeatureType::kVertex);
    EXPECT_NEAR((s.normal + Vec3::UnitZ()).norm(), 0.0, 1e-15);
    EXPECT_NEAR(s.gap, kDepth, 1e-15);
    EXPECT_NEAR(s.weight, 0.25, 1e-14);
  }
}

// A cube overlapping the corner of a plate: the overlap (0.75 x 0.5) has one cube vertex inside
// the plate, one plate vertex inside the cube, and two crossings of a cube edge with a plate edge.
// Weights: a rectangle's corners, a quarter each.
TEST(FaceContact, PartialOverlapHasCrossingsAndPlateCorner) {
  Placed a(boxShape(Vec3(0.5, 0.5, 0.5)), Vec3(0.25, 0.0, 0.5 - kDepth), Mat3::Identity());
  Placed b(boxShape(Vec3(0.5, 0.3, 0.5)), Vec3(0.0, 0.3, -0.5), Mat3::Identity());
  // Plate x in [-0.5, 0.5], y in [0, 0.6]; cube x in [-0.25, 0.75], y in [-0.5, 0.5].
  FaceContactBuilder builder;
  const auto fc =
      builder.build(a.body(), b.body(), along(Vec3::UnitZ(), Vec3(0.1, 0.2, 0), kDepth));
  ASSERT_EQ(fc.kind, ContactArea::kFace);
  ASSERT_EQ(fc.subs.size(), 4u);
  EXPECT_NEAR(fc.area, 0.75 * 0.5, 1e-12);
  int vertex_in_face = 0, face_with_vertex = 0, crossings = 0;
  Vec3 centre = Vec3::Zero();
  for (const auto& s : fc.subs) {
    const auto ta = featureType(static_cast<std::uint32_t>(s.feature >> 32));
    const auto tb = featureType(static_cast<std::uint32_t>(s.feature));
    vertex_in_face += ta == FeatureType::kVertex && tb == FeatureType::kFace;
    face_with_vertex += ta == FeatureType::kFace && tb == FeatureType::kVertex;
    crossings += ta == FeatureType::kEdge && tb == FeatureType::kEdge;
    EXPECT_NEAR(s.gap, kDepth, 1e-15);
    EXPECT_NEAR(s.weight, 0.25, 1e-12);
    centre += s.weight * s.point;
  }
  EXPECT_EQ(vertex_in_face, 1);
  EXPECT_EQ(face_with_vertex, 1);
  EXPECT_EQ(crossings, 2);
  EXPECT_NEAR(centre.x(), 0.125, 1e-12);
  EXPECT_NEAR(centre.y(), 0.25, 1e-12);
  EXPECT_NEAR(weightSum(fc), 1.0, 1e-14);
}

// A triangle of overlap: every corner gets a third, so a uniform gap acts at the centroid.
TEST(FaceContact, TriangularOverlapWeighsCornersEqually) {
  // A prism with a right-triangle cross-section (legs 1 along x and y) standing on a plate.
  const std::vector<Vec3> prism{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {0, 1, 1}};
  Placed a(geometry::ConvexPolyhedron::fromPoints(prism), Vec3(0, 0, -kDepth), Mat3::Identity());
  Placed b(boxShape(Vec3(5, 5, 0.5)), Vec3(0, 0, -0.5), Mat3::Identity());
  FaceContactBuilder builder;
  const auto fc =
      builder.build(a.body(), b.body(), along(Vec3::UnitZ(), Vec3(0.3, 0.3, 0), kDepth));
  ASSERT_EQ(fc.kind, ContactArea::kFace);
  ASSERT_EQ(fc.subs.size(), 3u);
  for (const auto& s : fc.subs) EXPECT_NEAR(s.weight, 1.0 / 3.0, 1e-14);
}

// Tilted by a small angle about x: the gaps grow linearly across the face, each measured along
// the plate's normal at the cube's own corners.
TEST(FaceContact, TiltedCubeHasLinearGaps) {
  const double tilt = 1e-4;
  const Mat3 r = about(Vec3::UnitX(), tilt);
  Placed a(boxShape(Vec3(0.5, 0.5, 0.5)), Vec3(0, 0, 0.5 - kDepth), r);
  Placed b(boxShape(Vec3(5, 5, 0.5)), Vec3(0, 0, -0.5), Mat3::Identity());
  FaceContactBuilder builder;
  const auto fc = builder.build(a.body(), b.body(), along(Vec3::UnitZ(), Vec3::Zero(), kDepth));
  ASSERT_EQ(fc.kind, ContactArea::kFace);
  ASSERT_EQ(fc.subs.size(), 4u);
  for (const auto& s : fc.subs) {
    const int v = featureIndex(static_cast<std::uint32_t>(s.feature >> 32));
    const Vec3& corner = a.body().vertices[v];
    EXPECT_NEAR(s.gap, -corner.z(), 1e-15) << "depth of the corner below the plate";
    EXPECT_NEAR(s.point.z(), 0.5 * corner.z(), 1e-15);
  }
}

// A cube lying on an edge (turned 45 degrees about x): a line contact, the two ends of the edge,
// half the weight each.
TEST(FaceContact, CubeOnItsEdgeIsALine) {
  const Mat3 r = about(Vec3::UnitX(), std::numbers::pi / 4);
  const double h = 0.5 * std::sqrt(2.0);
  Placed a(boxShape(Vec3(0.5, 0.5, 0.5)), Vec3(0.2, 0, h - kDepth), r);
  Placed b(boxShape(Vec3(5, 5, 0.5)), Vec3(0, 0, -0.5), Mat3::Identity());
  FaceContactBuilder builder;
  const auto fc = builder.build(a.body(), b.body(), along(Vec3::UnitZ(), Vec3(0.2, 0, 0), kDepth));
  ASSERT_EQ(fc.kind, ContactArea::kLine);
  ASSERT_EQ(fc.subs.size(), 2u);
  EXPECT_NEAR(std::abs(fc.subs[0].point.x() - fc.subs[1].point.x()), 1.0, 1e-12);
  for (const auto& s : fc.subs) {
    EXPECT_NEAR(s.weight, 0.5, 0.0);
    EXPECT_NEAR(s.gap, kDepth, 1e-12);
    EXPECT_NEAR(std::abs(s.point.x() - 0.2), 0.5, 1e-12);
  }
}

// Corner down: no face within the facing angle, no edge parallel to the plate: the kernel's point.
TEST(FaceContact, CornerDownKeepsTheKernelsPoint) {
  const Mat3 r = about(Vec3(1, -1, 0), std::atan(std::sqrt(2.0)));  // a body diagonal along z
  Placed a(boxShape(Vec3(0.5, 0.5, 0.5)), Vec3(0, 0, 0.5 * std::sqrt(3.0) - kDepth), r);
  Placed b(boxShape(Vec3(5, 5, 0.5)), Vec3(0, 0, -0.5), Mat3::Identity());
  FaceContactBuilder builder;
  const Contact c = along(Vec3::UnitZ(), Vec3(0, 0, -0.5 * kDepth), kDepth);
  const auto fc = builder.build(a.body(), b.body(), c);
  ASSERT_EQ(fc.kind, ContactArea::kPoint);
  ASSERT_EQ(fc.subs.size(), 1u);
  EXPECT_EQ(fc.subs[0].feature, 0u);
  EXPECT_EQ(fc.subs[0].weight, 1.0);
  EXPECT_EQ(fc.subs[0].gap, kDepth);
  EXPECT_EQ(fc.subs[0].point, c.point);
}

// Two equal cubes stacked exactly (every edge of one on an edge of the other): degenerate
// clipping; still four corners of a quarter each, each feature once.
TEST(FaceContact, StackedEqualCubesAreDegenerateButWhole) {
  Placed a(boxShape(Vec3(0.5, 0.5, 0.5)), Vec3(0, 0, 1.0 - kDepth), Mat3::Identity());
  Placed b(boxShape(Vec3(0.5, 0.5, 0.5)), Vec3(0, 0, 0), Mat3::Identity());
  FaceContactBuilder builder;
  const auto fc = builder.build(a.body(), b.body(), along(Vec3::UnitZ(), Vec3(0, 0, 0.5), kDepth));
  ASSERT_EQ(fc.kind, ContactArea::kFace);
  ASSERT_EQ(fc.subs.size(), 4u);
  EXPECT_NEAR(fc.area, 1.0, 1e-12);
  for (std::size_t i = 1; i < fc.subs.size(); ++i)
    EXPECT_LT(fc.subs[i - 1].feature, fc.subs[i].feature);
  for (const auto& s : fc.subs) {
    EXPECT_NEAR(s.weight, 0.25, 1e-12);
    EXPECT_NEAR(s.gap, kDepth, 1e-15);
  }
}

// Faces overlapping in slivers (down to 1e-12 of the size wide, nearly parallel edges): whatever
// kind comes out, the weights are finite, never negative, and sum to 1, the points lie near the
// overlap. (Shares taken from a round-off-polluted area centroid once gave weights of +-484.)
TEST(FaceContact, SliversHaveSaneWeights) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  FaceContactBuilder builder;
  int faces = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    const double width = std::pow(10.0, -12.0 + 11.0 * (0.5 + 0.5 * u(rng)));
    const double turn = 1e-6 * u(rng);
    const Vec3 x(1.0 - width, 0.3 * u(rng), 1.0 - kDepth);
    Placed a(boxShape(Vec3(0.5, 0.5, 0.5)), x, about(Vec3::UnitZ(), turn));
    Placed b(boxShape(Vec3(0.5, 0.5, 0.5)), Vec3::Zero(), Mat3::Identity());
    const auto fc =
        builder.build(a.body(), b.body(), along(Vec3::UnitZ(), Vec3(0.5, x.y(), 0.5), kDepth));
    faces += fc.kind == ContactArea::kFace;
    double sum = 0.0;
    for (const auto& s : fc.subs) {
      ASSERT_TRUE(std::isfinite(s.weight) && s.weight >= 0.0) << "weight " << s.weight;
      ASSERT_TRUE(s.point.allFinite() && std::isfinite(s.gap));
      EXPECT_LT(std::abs(s.point.x() - 0.5), width + 1e-6) << "width " << width;
      sum += s.weight;
    }
    EXPECT_NEAR(sum, 1.0, 1e-12);
  }
  EXPECT_GT(faces, 0);
}

// Random polyhedra put face to face (a random face of A turned onto a random face of B, slid in
// the plane so that the overlap ranges from whole faces to corners barely touching, tilted by up to
// 1e-6 rad): the same guarantees as above.
TEST(FaceContact, RandomFacePairsHaveSaneWeights) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  auto cloud = [&](int n) {
    std::vector<Vec3> points;
    for (int i = 0; i < n; ++i) points.push_back(Vec3(u(rng), u(rng), 0.6 * u(rng)));
    return geometry::ConvexPolyhedron::fromPoints(points);
  };
  FaceContactBuilder builder;
  int faces = 0;
  for (int trial = 0; trial < 3000; ++trial) {
    const auto sa = cloud(8 + trial % 20), sb = cloud(8 + (trial / 7) % 20);
    const auto& fa = sa.faces()[trial % sa.faces().size()];
    const auto& fb = sb.faces()[(trial / 3) % sb.faces().size()];
    // B's face to z = 0 facing up; A's face onto it facing down, turned and slid in the plane.
    const Mat3 rb = Eigen::Quaterniond::FromTwoVectors(fb.normal, Vec3::UnitZ()).toRotationMatrix();
    const Vec3 xb = -(rb * fb.centroid);
    const Mat3 ra =
        about(Vec3(u(rng), u(rng), 0.0), 1e-6 * u(rng)) * about(Vec3::UnitZ(), 3 * u(rng)) *
        Eigen::Quaterniond::FromTwoVectors(fa.normal, -Vec3::UnitZ()).toRotationMatrix();
    const double reach = std::sqrt(fa.area) + std::sqrt(fb.area);
    const Vec3 slide(0.6 * reach * u(rng), 0.6 * reach * u(rng), 0.0);
    const Vec3 xa = slide - ra * fa.centroid - kDepth * Vec3::UnitZ();
    Placed a(sa, xa, ra), b(sb, xb, rb);
    const auto fc = builder.build(a.body(), b.body(), along(Vec3::UnitZ(), slide, kDepth));
    faces += fc.kind == ContactArea::kFace;
    double sum = 0.0;
    for (const auto& s : fc.subs) {
      ASSERT_TRUE(std::isfinite(s.weight) && s.weight >= 0.0) << "weight " << s.weight;
      ASSERT_TRUE(s.point.allFinite() && std::isfinite(s.gap));
      sum += s.weight;
    }
    EXPECT_NEAR(sum, 1.0, 1e-12);
  }
  EXPECT_GT(faces, 1000);
}

// Under a rigid motion of the pair the labels and weights are the same and the points and
// normals move with it; in millimetres everything scales.
TEST(FaceContact, RigidMotionAndUnitChangeGiveTheSameSubContacts) {
  std::mt19937_64 rng(7);
  const Mat3 tilt = about(Vec3(1, 2, 0), 3e-4);
  auto make = [&](const Mat3& r, const Vec3& t, double scale, FaceContactBuilder& builder,
                  std::vector<SubContact>& out) {
    Placed a(boxShape(scale * Vec3(0.5, 0.4, 0.3)), t + r * (scale * Vec3(0.3, 0.1, 0.3 - kDepth)),
             r * tilt);
    Placed b(boxShape(scale * Vec3(0.6, 0.5, 0.5)), t + r * (scale * Vec3(0, 0, -0.5)), r);
    const auto fc = builder.build(
        a.body(), b.body(),
        along(r * Vec3::UnitZ(), t + r * (scale * Vec3(0.3, 0.1, 0)), scale * kDepth));
    out.assign(fc.subs.begin(), fc.subs.end());
    return fc.kind;
  };
  FaceContactBuilder builder;
  std::vector<SubContact> ref, got;
  ASSERT_EQ(make(Mat3::Identity(), Vec3::Zero(), 1.0, builder, ref), ContactArea::kFace);
  ASSERT_GE(ref.size(), 4u);
  for (int trial = 0; trial < 5; ++trial) {
    const Mat3 r = testing::randomRotation(rng);
    const Vec3 t = 100.0 * testing::randomUnit(rng);
    for (double scale : {1.0, 1e-3, 1e3}) {
      ASSERT_EQ(make(r, scale * t, scale, builder, got), ContactArea::kFace);
      ASSERT_EQ(got.size(), ref.size());
      for (std::size_t i = 0; i < ref.size(); ++i) {
        EXPECT_EQ(got[i].feature, ref[i].feature);
        EXPECT_NEAR(got[i].weight, ref[i].weight, 1e-9);
        EXPECT_NEAR(got[i].gap / scale, ref[i].gap, 1e-9 * kDepth);
        EXPECT_NEAR(((got[i].point - scale * t) / scale - r * ref[i].point).norm(), 0.0, 1e-9);
        EXPECT_NEAR((got[i].normal - r * ref[i].normal).norm(), 0.0, 1e-12);
      }
    }
  }
}

// The corner forces kn w g n are minus the gradient of E = sum kn w max(g, 0)^2 / 2 with respect
// to a rigid displacement of A (translation and small rotation): the normal force is conservative.
TEST(FaceContact, CornerForcesAreTheGradientOfTheSpringEnergy) {
  const Mat3 tilt = about(Vec3(1, 0.3, 0), 2e-4);
  const Vec3 xa(0.1, 0.05, 0.5 - kDepth);
  Placed b(boxShape(Vec3(0.7, 0.6, 0.5)), Vec3(0, 0, -0.5), Mat3::Identity());
  FaceContactBuilder builder;
  const double kn = 1e8;
  auto energy = [&](const Vec3& x, const Mat3& r, Vec3* force, Vec3* torque) {
    Placed a(boxShape(Vec3(0.5, 0.5, 0.5)), x, r);
    const auto fc =
        builder.build(a.body(), b.body(), along(Vec3::UnitZ(), Vec3(0.1, 0, 0), kDepth));
    double e = 0.0;
    if (force) force->setZero(), torque->setZero();
    for (const auto& s : fc.subs) {
      if (s.gap <= 0.0) continue;
      e += 0.5 * kn * s.weight * s.gap * s.gap;
      if (force) {
        const Vec3 f = kn * s.weight * s.gap * s.normal;
        *force += f;
        *torque += (s.point - x).cross(f);
      }
    }
    return e;
  };
  Vec3 force, torque;
  energy(xa, tilt, &force, &torque);
  const double h = 1e-9, hr = 1e-9;
  for (int k = 0; k < 3; ++k) {
    const Vec3 d = h * Vec3::Unit(k);
    const double de =
        energy(xa + d, tilt, nullptr, nullptr) - energy(xa - d, tilt, nullptr, nullptr);
    EXPECT_NEAR(-de / (2 * h), force[k], 1e-5 * force.norm()) << "translation " << k;
    const Mat3 plus = about(Vec3::Unit(k), hr) * tilt, minus = about(Vec3::Unit(k), -hr) * tilt;
    // Turning A about its centroid: the corners move, the centroid does not.
    const double dr = energy(xa, plus, nullptr, nullptr) - energy(xa, minus, nullptr, nullptr);
    EXPECT_NEAR(-dr / (2 * hr), torque[k], 1e-5 * force.norm()) << "rotation " << k;
  }
}

}  // namespace
}  // namespace polydem::contact
