// The distance-potential kernel (Zhao et al. sections 3.1-3.2) against analytical answers: the
// potential is the distance to the surface over the inradius; slab overlaps of boxes in closed
// form; the seven contact types of BENCHMARKS.md C (right on all seven), under rigid motions and
// changes of unit; shape independence (Zhao figs. 3-4, 10); the work along closed paths (the
// force is conservative); random pairs against the brute-force boundary integral; degenerate
// inputs and the inner domain.
#include "polydem/contact/potential/distance_potential.h"

#include <gtest/gtest.h>

#include <cstdio>

#include "polydem/contact/contact_cases.h"
#include "polydem/geometry/shapes.h"
#include "potential_test_util.h"

namespace polydem::contact {
namespace {

namespace shapes = geometry::shapes;
using testing::LoopWork;
using testing::place;
using testing::Placed;
using testing::RandomPair;
using testing::randomPair;

const DistancePotentialKernel kKernel;

Vec3 unitZ() {
  return Vec3::UnitZ();
}

// The exact integral over an a x b rectangle of min(delta, distance to its boundary):
// integral over s in [0, delta] of the area farther than s, (a - 2s)(b - 2s).
double rimIntegral(double a, double b, double delta) {
  return a * b * delta - (a + b) * delta * delta + 4.0 * delta * delta * delta / 3.0;
}

// ---------------------------------------------------------------------------------------------
// The potential itself: the claim behind the kernel (Zhao eq. 5 on the sub-polyhedra of figs.
// 7-9 is min_i d_i / r, the distance to the surface over r).

TEST(DistancePotential, MinOverPlanesIsTheDistanceToTheSurfaceOnIrregularShapes) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<std::vector<Vec3>> clouds = {
      {{0, 0, 0}, {1.6, 0, 0}, {0.3, 1.1, 0}, {0.5, 0.4, 0.9}},  // irregular tetrahedron
      shapes::box({-2, -0.5, -0.3}, {2, 0.5, 0.3}),              // long box: inner segment
      shapes::ridgePrism({-1, 0, 0}, {1, 0, 0}, 0.5, 1.0),       // wedge
  };
  for (int n : {8, 15, 40}) clouds.push_back(shapes::randomConvex(n, 100 + n, {1, 0.7, 0.5}, 0.2));
  for (const auto& cloud : clouds) {
    const auto p = geometry::ConvexPolyhedron::fromPoints(cloud);
    const double tol = 1e-12 * p.lengthScale();
    int inside = 0;
    double deepest = 0.0;
    for (int k = 0; k < 4000; ++k) {
      const Vec3 x = p.centroid() + p.circumradius() * Vec3(u(rng), u(rng), u(rng));
      if (!p.contains(x)) continue;
      ++inside;
      const double planes = testing::planeClearance(p, x);
      EXPECT_NEAR(planes, testing::distanceToSurface(p, x), tol);
      deepest = std::max(deepest, planes);
    }
    EXPECT_GT(inside, 100);
    // phi = distance / r never exceeds 1: r is the largest clearance.
    EXPECT_LE(deepest, p.inradius() * (1.0 + 1e-12));
    EXPECT_NEAR(testing::planeClearance(p, p.incenter()), p.inradius(), tol);
  }
}

// ---------------------------------------------------------------------------------------------
// Slab overlaps: f = delta * area / r_B on A's face (phi_B = delta / r_B there) plus
// (1 / r_A) * integral of min(delta, distance to the patch rim) on B's face, which is
// delta * area * (1/r_A + 1/r_B) to first order in delta.

struct SlabCase {
  Vec3 a_half;       // half extents of A (above)
  Vec3 b_lo, b_hi;   // B (below), top at z = 0
  Vec3 a_centre_xy;  // where A's bottom face is centred
  double turn;       // A turned about z
};

TEST(DistancePotential, SlabOverlapOfBoxesHasTheClosedForm) {
  const std::vector<SlabCase> cases = {
      {{0.5, 0.5, 0.5}, {-1.2, -1.5, -1}, {2.8, 2.5, 0}, {0, 0, 0}, 0.0},   // C-FF's cubes
      {{0.5, 0.3, 0.2}, {-2, -2, -1.5}, {2, 2, 0}, {0.4, -0.3, 0}, 0.0},    // r_A = 0.2
      {{0.5, 0.3, 0.2}, {-2, -2, -1.5}, {2, 2, 0}, {-0.2, 0.5, 0}, 0.7},    // turned
      {{0.25, 0.75, 0.6}, {-3, -1, -0.4}, {1, 2, 0}, {-1.1, 0.2, 0}, 0.0},  // r_B = 0.2
  };
  for (double delta : {1e-5, 1e-3}) {
    for (const auto& c : cases) {
      const Mat3 turn = testing::rotationAbout(unitZ(), c.turn);
      const Vec3 centre = c.a_centre_xy + Vec3(0, 0, c.a_half.z() - delta);
      auto a = place(shapes::boxAround(Vec3::Zero(), c.a_half), centre, turn);
      auto b = place(shapes::box(c.b_lo, c.b_hi));
      const double ax = 2 * c.a_half.x(), ay = 2 * c.a_half.y();
      const double r_a = a.shape->inradius(), r_b = b.shape->inradius();
      EXPECT_NEAR(r_a, c.a_half.minCoeff(), 1e-12);
      const double expected = delta * ax * ay / r_b + rimIntegral(ax, ay, delta) / r_a;

      const auto res = kKernel.evaluate(a.body, b.body);
      const Contact& r = res.contact;
      ASSERT_TRUE(r.touching);
      EXPECT_EQ(r.status, Status::kOk);
      EXPECT_EQ(r.model, ForceModel::kPotential);
      EXPECT_NEAR(r.potential, expected, 1e-11 * expected);
      // The leading-order form of the brief holds to O(delta / size).
      const double leading = delta * ax * ay * (1.0 / r_a + 1.0 / r_b);
      EXPECT_NEAR(r.potential / leading, 1.0,
                  2.0 * delta * (ax + ay) / (ax * ay) / (1 + r_a / r_b));
      EXPECT_LT(angleBetween(r.normal, unitZ()), 1e-12);
      EXPECT_LT((r.point - Vec3(centre.x(), centre.y(), -0.5 * delta)).norm(), 1e-12);
      EXPECT_NEAR(r.depth, delta, 1e-12);
      EXPECT_LT(std::abs(res.torsion), 1e-12 * r.potential);
    }
  }
}

TEST(DistancePotential, SlabWithTheSmallerBodyBelowSwapsTheRoles) {
  const double delta = 1e-4;
  // A large plate above, B a small box below whose top face is the patch.
  auto a = place(shapes::box({-2, -2, -delta}, {2, 2, 1 - delta}));
  auto b = place(shapes::box({-0.3, -0.2, -0.5}, {0.3, 0.2, 0}));
  const double expected =
      delta * 0.6 * 0.4 / a.shape->inradius() + rimIntegral(0.6, 0.4, delta) / b.shape->inradius();
  const Contact r = kKernel.collide(a.body, b.body, nullptr);
  ASSERT_TRUE(r.touching);
  EXPECT_NEAR(r.potential, expected, 1e-11 * expected);
  EXPECT_LT(angleBetween(r.normal, unitZ()), 1e-12);
  EXPECT_LT((r.point - Vec3(0, 0, -0.5 * delta)).norm(), 1e-12);
}

// ---------------------------------------------------------------------------------------------
// The seven contact types: the force is vertical through the z axis, by the pair's symmetry
// (C-VV, C-VE, C-VF, C-EEx) or because B's potential in the overlap depends only on the depth
// below B's face (C-EEp, C-EF, C-FF); the point half way across the overlap is (0, 0, -5e-6).

TEST(DistancePotential, AllSevenContactTypesAreRight) {
  for (const auto& c : contactTypeCases()) {
    auto a = place(c.a), b = place(c.b);
    const Contact r = kKernel.collide(a.body, b.body, nullptr);
    const auto e = evaluate(c, r);
    EXPECT_TRUE(e.correct()) << c.id << ": normal error " << e.normal_error_rad << " rad, point "
                             << e.point_error;
    EXPECT_EQ(r.status, Status::kOk) << c.id;
    EXPECT_NEAR(r.depth, c.depth, 1e-12) << c.id;
    std::printf("%-6s normal error %.1e rad, point error %.1e, potential %.6e m^2\n", c.id.c_str(),
                e.normal_error_rad, e.point_error, r.potential);
  }
}

TEST(DistancePotential, SevenContactTypesStayRightUnderRigidMotionsAndUnits) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-5.0, 5.0);
  for (const auto& base : contactTypeCases()) {
    auto a0 = place(base.a), b0 = place(base.b);
    const double p0 = kKernel.collide(a0.body, b0.body, nullptr).potential;
    for (double scale : {1e-3, 1.0, 1e3}) {
      for (int k = 0; k < 4; ++k) {
        const Mat3 rot = testing::randomRotation(rng);
        const Vec3 t = scale * Vec3(u(rng), u(rng), u(rng));
        const ContactCase c = transformed(base, rot, t, scale);
        // Shapes built in the world frame ...
        auto a = place(c.a), b = place(c.b);
        const Contact r = kKernel.collide(a.body, b.body, nullptr);
        EXPECT_TRUE(evaluate(c, r).correct()) << base.id << " scale " << scale;
        EXPECT_NEAR(r.potential, p0 * scale * scale, 1e-9 * p0 * scale * scale) << base.id;
        EXPECT_NEAR(r.depth, c.depth, 1e-9 * c.depth) << base.id;
        // ... and the unit-size shapes placed by position and rotation, scaled.
        std::vector<Vec3> sa, sb;
        for (const Vec3& x : base.a) sa.push_back(scale * x);
        for (const Vec3& x : base.b) sb.push_back(scale * x);
        auto pa = place(sa, t, rot), pb = place(sb, t, rot);
        EXPECT_TRUE(evaluate(c, kKernel.collide(pa.body, pb.body, nullptr)).correct()) << base.id;
      }
    }
  }
}

// ---------------------------------------------------------------------------------------------
// Shape independence (Zhao section 2.2, figs. 3-4 and 10): the same penetration of a face gives
// the same force whatever the face and whatever the tetrahedron, for a given inradius.

TEST(DistancePotential, SamePenetrationGivesTheSameForceOnEveryFaceOfAnyTetrahedron) {
  auto irregular = place({{0, 0, 0}, {1.6, 0, 0}, {0.3, 1.1, 0}, {0.5, 0.4, 0.9}});
  // The regular tetrahedron with the same inradius (r = edge / sqrt(24)).
  auto regular = place(shapes::tetrahedron(std::sqrt(24.0) * irregular.shape->inradius()));
  ASSERT_NEAR(regular.shape->inradius(), irregular.shape->inradius(), 1e-12);
  const double a = 0.05, delta = 1e-4;
  const double r_t = irregular.shape->inradius();
  const double expected = delta * a * a / r_t + rimIntegral(a, a, delta) / (0.5 * a);
  for (const Placed* t : {&irregular, &regular}) {
    for (int f = 0; f < 4; ++f) {
      double room = 0.0;
      const testing::Pressed p = testing::pressBoxOnFace(kKernel, *t, f, a, a, delta, &room);
      ASSERT_GT(room, a);  // the patch lies well inside the face
      EXPECT_NEAR(p.potential, expected, 1e-10 * expected) << "face " << f;
      EXPECT_LT(angleBetween(p.normal, t->shape->faces()[f].normal), 1e-10);
    }
  }
}

TEST(DistancePotential, VertexOnTheRidgeOfAnIrregularTetrahedronIsPushedAlongTheBisector) {
  // Zhao 5.1 (figs. 23-25): no sideways push. phi_B = min(d_1, d_2) / r is symmetric about the
  // bisector plane whatever the faces' sizes.
  auto b = place(testing::ridgeTetrahedron());
  for (double delta : {1e-5, 1e-3}) {
    auto a = place(testing::pyramidOnRidge(delta));
    const Contact r = kKernel.collide(a.body, b.body, nullptr);
    ASSERT_TRUE(r.touching);
    EXPECT_LT(angleBetween(r.normal, unitZ()), 1e-10) << delta;
    EXPECT_LT((r.point - Vec3(0, 0, -0.5 * delta)).norm(), 1e-12) << delta;
  }
}

TEST(DistancePotential, VertexOfAnIrregularTetrahedronIsPushedAlongTheFaceNormal) {
  // On the overlap's boundary phi_A is non-zero only on B's face (one plane), and phi_B varies
  // along B's normal only: both parts of the force are along that normal, however skew A's
  // vertex is.
  const std::vector<Vec3> tet = {{0, 0, 0}, {1.6, 0, 0}, {0.3, 1.1, 0}, {0.5, 0.4, 0.9}};
  const Vec3 centroid = geometry::ConvexPolyhedron::fromPoints(tet).centroid();
  auto box = place(shapes::box({-3, -3, -2}, {3, 3, 0}));
  for (int v = 0; v < 4; ++v) {
    // The vertex pointing down along its axis from the centroid, and tipped a little.
    const Mat3 rot =
        testing::rotationAbout(Vec3(1, 2, 0), 0.2) *
        Eigen::Quaterniond::FromTwoVectors(tet[v] - centroid, -unitZ()).toRotationMatrix();
    for (double delta : {1e-5, 1e-2}) {
      auto a = place(tet, Vec3(0.7, 1.1, -delta) - rot * tet[v], rot);
      const Contact r = kKernel.collide(a.body, box.body, nullptr);
      ASSERT_TRUE(r.touching);
      EXPECT_LT(angleBetween(r.normal, unitZ()), 1e-10) << v;
      EXPECT_NEAR(r.depth, delta, 1e-12) << v;
    }
  }
}

// ---------------------------------------------------------------------------------------------
// Energy: f = -grad E with E = penalty * integral over V of (phi_A + phi_B) dV (the boundary
// integral is the divergence form of it), so the work along a closed path vanishes, rotations
// included when the torsion is kept.

TEST(DistancePotential, WorkAlongClosedPathsVanishes) {
  testing::expectClosedLoopWorkVanishes(kKernel);
}

// ---------------------------------------------------------------------------------------------
// Random pairs against the independent reference (overlap polyhedron by clipping, boundary
// integral by quadrature), Newton's third law, units.

TEST(DistancePotential, RandomPairsMatchTheBruteForceBoundaryIntegral) {
  // Overlaps from 0.07 to 0.22 of bodies of size ~1, and a deep one (0.6).
  for (std::uint64_t seed = 1; seed <= 7; ++seed) {
    const RandomPair p = randomPair(seed, seed == 7 ? 0.6 : 0.04 + 0.03 * seed);
    const auto res = kKernel.evaluate(p.a.body, p.b.body);
    ASSERT_TRUE(res.contact.touching) << seed;
    const auto wa = testing::worldShape(p.a.body), wb = testing::worldShape(p.b.body);
    const auto v = testing::overlapPolyhedron(wa, wb);
    ASSERT_TRUE(v.has_value());
    const double ra = wa.inradius(), rb = wb.inradius();
    const auto ref = testing::quadrature(
        *v, [&](const Vec3& x) { return testing::planeClearance(wa, x) / ra; },
        [&](const Vec3& x) { return testing::planeClearance(wb, x) / rb; }, 40);
    const double fref = ref.force.norm();
    const Vec3 moment_origin = res.moment + res.contact.point.cross(res.force);
    const double size = p.a.body.circumradius() + p.b.body.circumradius();
    const double ferr = (res.force - ref.force).norm() / fref;
    const double merr = (moment_origin - ref.moment).norm() / (fref * size);
    std::printf(
        "seed %d: %zu+%zu vertices, |f| %.4e, force error %.1e, moment error %.1e, "
        "torsion/(|f| size) %.1e\n",
        int(seed), p.a.shape->vertices().size(), p.b.shape->vertices().size(), fref, ferr, merr,
        std::abs(res.torsion) / (fref * size));
    EXPECT_LT(ferr, 2e-3) << seed;
    EXPECT_LT(merr, 2e-3) << seed;
    // The depth is the overlap's extent along the normal.
    double lo = 1e300, hi = -1e300;
    for (const Vec3& x : v->vertices()) {
      lo = std::min(lo, res.contact.normal.dot(x));
      hi = std::max(hi, res.contact.normal.dot(x));
    }
    EXPECT_NEAR(res.contact.depth, hi - lo, 1e-9 * size);
  }
}

TEST(DistancePotential, AgreesWithTheDefinitionByDistanceToTheSurface) {
  // One pair with the potentials taken straight from the definition (distance to the nearest
  // point of the surface polygons), not from the min-over-planes formula.
  const RandomPair p = randomPair(3, 0.1);
  const auto res = kKernel.evaluate(p.a.body, p.b.body);
  const auto wa = testing::worldShape(p.a.body), wb = testing::worldShape(p.b.body);
  const auto v = testing::overlapPolyhedron(wa, wb);
  ASSERT_TRUE(v.has_value());
  const auto ref = testing::quadrature(
      *v, [&](const Vec3& x) { return testing::distanceToSurface(wa, x) / wa.inradius(); },
      [&](const Vec3& x) { return testing::distanceToSurface(wb, x) / wb.inradius(); }, 16);
  EXPECT_LT((res.force - ref.force).norm(), 1e-2 * ref.force.norm());
}

TEST(DistancePotential, SwappingThePairReversesTheForceAtTheSamePoint) {
  testing::expectSwappingThePairReversesTheForce(kKernel, 11, 14, /*same_depth=*/true);
}

TEST(DistancePotential, RandomPairsScaleWithTheUnit) {
  testing::expectRandomPairsScaleWithTheUnit(kKernel, 21, 24, /*check_depth=*/true);
}

TEST(DistancePotential, SameInputsGiveTheSameBits) {
  const RandomPair p = randomPair(31, 0.1);
  const Contact r1 = kKernel.collide(p.a.body, p.b.body, nullptr);
  const Contact r2 = DistancePotentialKernel().collide(p.a.body, p.b.body, nullptr);
  EXPECT_EQ(r1.potential, r2.potential);
  EXPECT_EQ(r1.normal, r2.normal);
  EXPECT_EQ(r1.point, r2.point);
  EXPECT_EQ(r1.depth, r2.depth);
}

// ---------------------------------------------------------------------------------------------
// Separated, touching and degenerate-but-valid pairs.

TEST(DistancePotential, SeparatedAndTouchingPairsDoNotTouch) {
  testing::expectSeparatedAndTouchingCubesDoNotTouch(kKernel);
  // The turned cubes moved closer do touch; an edge touching a face exactly does not.
  const Mat3 r45z = testing::rotationAbout(unitZ(), kPi / 4);
  auto d1 = place(shapes::cube(1.0), Vec3::Zero(), r45z);
  auto d3 = place(shapes::cube(1.0), Vec3(0.7, 0.7, 0.3), r45z);
  EXPECT_TRUE(kKernel.collide(d3.body, d1.body, nullptr).touching);
  const Mat3 r45 = testing::rotationAbout(Vec3(1, 0, 0), kPi / 4);
  auto b = place(shapes::cube(1.0));
  auto edge = place(shapes::cube(1.0), Vec3(0, 0, 0.5 + std::sqrt(0.5)), r45);
  EXPECT_FALSE(kKernel.collide(edge.body, b.body, nullptr).touching);
}

TEST(DistancePotential, IdenticalBodiesTouchWithNoForce) {
  auto a = place(shapes::randomConvex(12, 4));
  auto b = place(shapes::randomConvex(12, 4));
  const Contact r = kKernel.collide(a.body, b.body, nullptr);
  EXPECT_TRUE(r.touching);
  EXPECT_EQ(r.status, Status::kDegenerate);
  EXPECT_EQ(r.potential, 0.0);
  EXPECT_NEAR(r.normal.norm(), 1.0, 1e-15);
}

TEST(DistancePotential, BodyInsideAnotherIsPushedTowardsTheNearestFace) {
  // A small cube deep in a box, nearest to the top face: phi_B = (distance below the top) / r_B
  // on all of A, so f = -integral over A of grad phi_B = volume(A) / r_B upwards.
  const double a = 0.2;
  auto big = place(shapes::box({-2, -2, -1}, {2, 2, 0}));
  auto small = place(shapes::cube(a), Vec3(0.3, -0.4, -0.3));
  const Contact r = kKernel.collide(small.body, big.body, nullptr);
  ASSERT_TRUE(r.touching);
  // The overlap is all of A, so it holds A's inner domain (its centre): flagged, force given.
  EXPECT_EQ(r.status, Status::kInnerDomainReached);
  EXPECT_NEAR(r.potential, a * a * a / big.shape->inradius(), 1e-12);
  EXPECT_LT(angleBetween(r.normal, unitZ()), 1e-12);
  EXPECT_LT((r.point - Vec3(0.3, -0.4, -0.3)).norm(), 1e-12);
  EXPECT_NEAR(r.depth, a, 1e-12);
  // Newton's third law: the big box is pushed down.
  const Contact rb = kKernel.collide(big.body, small.body, nullptr);
  EXPECT_LT(angleBetween(rb.normal, -unitZ()), 1e-12);
}

TEST(DistancePotential, OverlapReachingTheInnerDomainIsFlagged) {
  // B: 4 x 1 x 1 box, inradius 0.5, inner domain the segment x in [-1.5, 1.5] on its axis. A: a
  // cube of side 2 (its own inner domain, its centre, stays 1 above its bottom face) pressed down
  // onto B's top; over x in [0.2, 2.2] it reaches the segment at depth 0.5.
  auto b = place(shapes::box({-2, -0.5, -0.5}, {2, 0.5, 0.5}));
  for (double depth : {0.3, 0.49, 0.51, 0.8}) {
    auto a = place(shapes::cube(2.0), Vec3(1.2, 0, 1.5 - depth));
    const Contact r = kKernel.collide(a.body, b.body, nullptr);
    ASSERT_TRUE(r.touching);
    EXPECT_EQ(r.status, depth > 0.5 ? Status::kInnerDomainReached : Status::kOk) << depth;
    EXPECT_GT(r.potential, 0.0);  // the force is still given
  }
  // Over x in [1.6, 3.6], beyond the segment's end, the same depths never reach it.
  for (double depth : {0.51, 0.8}) {
    auto a = place(shapes::cube(2.0), Vec3(2.6, 0, 1.5 - depth));
    EXPECT_EQ(kKernel.collide(a.body, b.body, nullptr).status, Status::kOk) << depth;
  }
}

TEST(DistancePotential, IsRegisteredUnderItsName) {
  const auto k = makeKernel("distance-potential");
  EXPECT_EQ(k->name(), "distance-potential");
  auto a = place(shapes::cube(1.0), Vec3(0, 0, 0.99));
  auto b = place(shapes::cube(1.0));
  EXPECT_TRUE(k->collide(a.body, b.body, nullptr).touching);
}

}  // namespace
}  // namespace polydem::contact
