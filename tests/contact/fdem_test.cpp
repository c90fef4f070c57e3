// The FDEM potential kernel (Munjiza 2004; Zhao et al. section 2) against analytical answers and
// against what Zhao section 2.2 says it gets wrong: its stiffness depends on the element's shape
// (figs. 3-4), and the potential vanishes on the internal faces of the split (valleys), which
// moves the point of action on face contacts (C-FF) and pushes sideways on ridges (Zhao 5.1).
#include "polydem/contact/potential/fdem.h"

#include <gtest/gtest.h>

#include <cstdio>

#include "polydem/contact/contact_cases.h"
#include "polydem/contact/potential/distance_potential.h"
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

const FdemKernel kKernel;

Vec3 unitZ() {
  return Vec3::UnitZ();
}

// ---------------------------------------------------------------------------------------------
// The seven contact types. Where both bodies' splits are symmetric about the contact (every case
// but C-FF) the force is vertical through the z axis; in C-FF the off-centre box's top face is
// fanned from its centre (0.8, 0.5) and one fan face, where the potential is zero, crosses the
// cube's footprint: a valley that moves the point of action.

bool symmetricCase(const std::string& id) {
  return id != "C-FF";
}

TEST(Fdem, SixOfTheSevenContactTypesAreRightAndCffIsRecorded) {
  for (const auto& c : contactTypeCases()) {
    auto a = place(c.a), b = place(c.b);
    const Contact r = kKernel.collide(a.body, b.body, nullptr);
    const auto e = evaluate(c, r);
    ASSERT_TRUE(r.touching) << c.id;
    std::printf("%-6s normal error %.1e rad, point error %.1e, potential %.6e m^2 %s\n",
                c.id.c_str(), e.normal_error_rad, e.point_error, r.potential,
                e.correct() ? "right" : "WRONG");
    if (symmetricCase(c.id)) {
      EXPECT_TRUE(e.correct()) << c.id;
      EXPECT_NEAR(r.depth, c.depth, 1e-12) << c.id;
    }
  }
}

TEST(Fdem, FaceContactIsRightWhenTheLowerFaceIsFannedSymmetricallyUnderIt) {
  // C-FF with the box centred under the cube: B's fan valleys (its top face's diagonals) cross
  // the footprint symmetrically, so the error of C-FF is the valley, not the face contact.
  ContactCase c = contactTypeCases().back();
  ASSERT_EQ(c.id, "C-FF");
  c.b = shapes::box({-2, -2, -1}, {2, 2, 0});
  auto a = place(c.a), b = place(c.b);
  const Contact r = kKernel.collide(a.body, b.body, nullptr);
  EXPECT_TRUE(evaluate(c, r).correct());
}

TEST(Fdem, RightContactTypesStayRightUnderRigidMotionsAndUnits) {
  std::mt19937_64 rng(13);
  std::uniform_real_distribution<double> u(-5.0, 5.0);
  for (const auto& base : contactTypeCases()) {
    if (!symmetricCase(base.id)) continue;
    auto a0 = place(base.a), b0 = place(base.b);
    const double p0 = kKernel.collide(a0.body, b0.body, nullptr).potential;
    for (double scale : {1e-3, 1.0, 1e3}) {
      for (int k = 0; k < 3; ++k) {
        const Mat3 rot = testing::randomRotation(rng);
        const Vec3 t = scale * Vec3(u(rng), u(rng), u(rng));
        const ContactCase c = transformed(base, rot, t, scale);
        auto a = place(c.a), b = place(c.b);
        const Contact r = kKernel.collide(a.body, b.body, nullptr);
        EXPECT_TRUE(evaluate(c, r).correct()) << base.id << " scale " << scale;
        EXPECT_NEAR(r.potential, p0 * scale * scale, 1e-9 * p0 * scale * scale) << base.id;
      }
    }
  }
}

// ---------------------------------------------------------------------------------------------
// The potential of one tetrahedron: d_i / (H_i / 4). For a tetrahedron with four faces of equal
// area H_i / 4 = 3V / (4 A_i) equals the inradius 3V / sum(A) on every face: FDEM and the
// distance potential are then the same function, and give the same force.

TEST(Fdem, EqualsTheDistancePotentialForTetrahedraWithEqualFaces) {
  const DistancePotentialKernel dp;
  // Regular tetrahedron and a disphenoid (opposite edges equal: four congruent faces).
  const std::vector<std::vector<Vec3>> solids = {
      shapes::tetrahedron(1.0), {{1, 0.8, 0.6}, {1, -0.8, -0.6}, {-1, 0.8, -0.6}, {-1, -0.8, 0.6}}};
  std::mt19937_64 rng(5);
  for (const auto& s : solids) {
    for (int k = 0; k < 4; ++k) {
      const RandomPair p = [&] {
        const Mat3 ra = testing::randomRotation(rng);
        auto b = place(s, Vec3::Zero(), testing::randomRotation(rng));
        const Vec3 dir = testing::randomRotation(rng) * unitZ();
        const double t = testing::touchingDistance(s, ra, testing::worldShape(b.body), dir);
        auto a = place(s, (t - 0.1) * dir, ra);  // the vertices are centred on the origin
        return RandomPair{std::move(a), std::move(b)};
      }();
      const Contact f = kKernel.collide(p.a.body, p.b.body, nullptr);
      const Contact d = dp.collide(p.a.body, p.b.body, nullptr);
      ASSERT_TRUE(f.touching);
      EXPECT_NEAR(f.potential, d.potential, 1e-12 * d.potential);
      EXPECT_LT(angleBetween(f.normal, d.normal), 1e-12);
      EXPECT_LT((f.point - d.point).norm(), 1e-12);
    }
  }
}

// ---------------------------------------------------------------------------------------------
// Shape dependence (Zhao figs. 3-4): a box pressed by delta onto face i of a tetrahedron gets
// 4 delta a^2 / H_i from the tetrahedron's potential plus a part P_A from its own that does not
// depend on i. The distance potential gives the same force on every face.

TEST(Fdem, SamePenetrationOfDifferentFacesGivesForcesInTheRatioOfTheirHeights) {
  const DistancePotentialKernel dp;
  auto t = place({{0, 0, 0}, {1.6, 0, 0}, {0.3, 1.1, 0}, {0.5, 0.4, 0.9}});
  // A tall box with a small foot (its own part 4 delta a^2 / (height / 2) is then not dominant).
  const double a = 0.05, height = 2.0, delta = 1e-4;
  std::vector<double> f, h;
  for (int i = 0; i < 4; ++i) {
    double room = 0.0;
    f.push_back(testing::pressBoxOnFace(kKernel, t, i, a, height, delta, &room).potential);
    ASSERT_GT(room, a);
    h.push_back(3.0 * t.shape->volume() / t.shape->faces()[i].area);  // height over face i
  }
  double spread = 0.0;
  for (int i = 1; i < 4; ++i) {
    const double expected = 4.0 * delta * a * a * (1.0 / h[i] - 1.0 / h[0]);
    EXPECT_NEAR(f[i] - f[0], expected, 1e-9 * f[0]) << "face " << i;
    spread = std::max(spread, std::abs(f[i] / f[0] - 1.0));
    const double d0 = testing::pressBoxOnFace(dp, t, 0, a, height, delta).potential;
    const double di = testing::pressBoxOnFace(dp, t, i, a, height, delta).potential;
    EXPECT_NEAR(di, d0, 1e-10 * d0);
  }
  std::printf(
      "FDEM: forces on the four faces differ by up to %.0f %% (heights %.3f %.3f %.3f %.3f)\n",
      100 * spread, h[0], h[1], h[2], h[3]);
  EXPECT_GT(spread, 0.1);
}

TEST(Fdem, SlabOverlapOfACubeOnABoxHasTheClosedForm) {
  // Unit cube A on a 4 x 4 x 0.6 box B, both centred. Far from internal faces phi = k delta with
  // k = 4 / H (H: the fan tetrahedra's height over the face, the centroid's distance to it):
  // k_A = 8, k_B = 4 / 0.3. Across a valley (an internal face meeting the contact plane) phi =
  // min(k delta, k' s), s the distance to the valley line, k' = 4 / (the tetrahedron's height over
  // that internal face): the deficit per unit length is (k delta)^2 / k'. The valleys are B's
  // top-face diagonals (k' = 4 / (2 sqrt 2)) and A's bottom-face diagonals (k' = 4 / (sqrt 2 /
  // 2)), each sqrt 2 long in the footprint, and A's rim: at height delta and distance s from a
  // bottom edge A's potential is 8 min(s, delta - s) for s < delta (the side face's tetrahedron,
  // cut by the internal plane through the edge and the centroid), then 8 (s - delta) up to s = 2
  // delta, a deficit of 10 delta^2 per unit length. Valley crossings and corners: O(delta^3).
  const double k_a = 8.0, k_b = 4.0 / 0.3;
  const double ki_b = 4.0 / (2.0 * std::sqrt(2.0)), ki_a = 4.0 / (0.5 * std::sqrt(2.0));
  const double deficit = 2.0 * std::sqrt(2.0) * (k_b * k_b / ki_b + k_a * k_a / ki_a) + 4.0 * 10.0;
  for (double delta : {1e-5, 1e-4}) {
    auto a = place(shapes::cube(1.0), Vec3(0, 0, 0.5 - delta));
    auto b = place(shapes::box({-2, -2, -0.6}, {2, 2, 0}));
    const Contact r = kKernel.collide(a.body, b.body, nullptr);
    const double leading = delta * (k_a + k_b);
    const double expected = leading - deficit * delta * delta;
    std::printf("delta %.0e: FDEM slab / leading order - 1 = %.4e, / with valleys - 1 = %.2e\n",
                delta, r.potential / leading - 1, r.potential / expected - 1);
    EXPECT_NEAR(r.potential / expected, 1.0, 200.0 * delta * delta);
    EXPECT_LT(angleBetween(r.normal, unitZ()), 1e-12);
    EXPECT_LT((r.point - Vec3(0, 0, -0.5 * delta)).norm(), 1e-12);
  }
}

TEST(Fdem, VertexOnTheRidgeOfAnIrregularTetrahedronIsPushedSideways) {
  // Zhao 5.1 (fig. 24): phi_B = min(4 d_1 / H_1, 4 d_2 / H_2) with H_1 != H_2 is not symmetric
  // about the bisector plane; the distance potential's force is vertical here (its own test).
  auto b = place(testing::ridgeTetrahedron());
  for (double delta : {1e-5, 1e-3}) {
    auto a = place(testing::pyramidOnRidge(delta));
    const Contact r = kKernel.collide(a.body, b.body, nullptr);
    ASSERT_TRUE(r.touching);
    const double tilt = angleBetween(r.normal, unitZ());
    std::printf("delta %.0e: FDEM tilt %.3f rad towards y = %+.3f\n", delta, tilt, r.normal.y());
    EXPECT_GT(tilt, 0.05);
    EXPECT_LT(std::abs(r.normal.x()), 1e-10);  // still symmetric along the ridge
  }
}

// ---------------------------------------------------------------------------------------------
// Energy: FDEM's force is also f = -grad E, E = penalty * integral over V of (phi_A + phi_B) dV
// (the potentials are continuous and vanish on the surfaces): closed paths do no work.

TEST(Fdem, WorkAlongClosedPathsVanishes) {
  testing::expectClosedLoopWorkVanishes(kKernel);
}

// ---------------------------------------------------------------------------------------------
// Random pairs against the independent reference: overlap polyhedron by clipping, potential from
// barycentric coordinates in the split's tetrahedra, boundary integral by quadrature.

TEST(Fdem, RandomPairsMatchTheBruteForceBoundaryIntegral) {
  for (std::uint64_t seed = 1; seed <= 4; ++seed) {
    const RandomPair p = randomPair(seed, 0.04 + 0.03 * seed);
    const auto res = kKernel.evaluate(p.a.body, p.b.body);
    ASSERT_TRUE(res.contact.touching) << seed;
    const auto wa = testing::worldShape(p.a.body), wb = testing::worldShape(p.b.body);
    const auto v = testing::overlapPolyhedron(wa, wb);
    ASSERT_TRUE(v.has_value());
    const testing::FdemPotential phi_a(testing::fdemTetrahedra(wa)),
        phi_b(testing::fdemTetrahedra(wb));
    const auto ref = testing::quadrature(*v, std::cref(phi_a), std::cref(phi_b), 32);
    const double fref = ref.force.norm();
    const double size = p.a.body.circumradius() + p.b.body.circumradius();
    const Vec3 moment_origin = res.moment + res.contact.point.cross(res.force);
    const double ferr = (res.force - ref.force).norm() / fref;
    const double merr = (moment_origin - ref.moment).norm() / (fref * size);
    std::printf("seed %d: |f| %.4e, force error %.1e, moment error %.1e\n", int(seed), fref, ferr,
                merr);
    EXPECT_LT(ferr, 2e-3) << seed;
    EXPECT_LT(merr, 2e-3) << seed;
  }
}

TEST(Fdem, SwappingThePairReversesTheForceAtTheSamePoint) {
  testing::expectSwappingThePairReversesTheForce(kKernel, 11, 13, /*same_depth=*/false);
}

TEST(Fdem, RandomPairsScaleWithTheUnit) {
  testing::expectRandomPairsScaleWithTheUnit(kKernel, 21, 23, /*check_depth=*/false);
}

// ---------------------------------------------------------------------------------------------
// Separated, touching and degenerate-but-valid pairs.

TEST(Fdem, SeparatedAndTouchingPairsDoNotTouch) {
  testing::expectSeparatedAndTouchingCubesDoNotTouch(kKernel);
}

TEST(Fdem, IdenticalBodiesTouchWithNoForce) {
  auto a = place(shapes::randomConvex(12, 4));
  auto b = place(shapes::randomConvex(12, 4));
  const Contact r = kKernel.collide(a.body, b.body, nullptr);
  EXPECT_TRUE(r.touching);
  EXPECT_EQ(r.status, Status::kDegenerate);
  EXPECT_EQ(r.potential, 0.0);
}

TEST(Fdem, BodyInsideAnotherIsPushedTowardsTheNearestFace) {
  // A small cube inside a box, in the fan tetrahedron of its top face away from the fan's
  // internal faces: phi_B = 4 (distance below the top) / H_B on all of A, f = 4 volume(A) / H_B.
  const double a = 0.1;
  auto big = place(shapes::box({-2, -2, -4}, {2, 2, 0}));  // H_B = 2
  auto small = place(shapes::cube(a), Vec3(1.0, 0.0, -0.15));
  const Contact r = kKernel.collide(small.body, big.body, nullptr);
  ASSERT_TRUE(r.touching);
  EXPECT_NEAR(r.potential, 4.0 * a * a * a / 2.0, 1e-12);
  EXPECT_LT(angleBetween(r.normal, unitZ()), 1e-12);
  EXPECT_LT((r.point - Vec3(1.0, 0.0, -0.15)).norm(), 1e-12);
}

TEST(Fdem, IsRegisteredUnderItsName) {
  const auto k = makeKernel("fdem");
  EXPECT_EQ(k->name(), "fdem");
  EXPECT_EQ(kernelNames().back(), "fdem");
  auto a = place(shapes::cube(1.0), Vec3(0, 0, 0.99));
  auto b = place(shapes::cube(1.0));
  EXPECT_TRUE(k->collide(a.body, b.body, nullptr).touching);
}

}  // namespace
}  // namespace polydem::contact
