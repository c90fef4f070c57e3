// Kernels gjk-epa and gjk-epa-ipm: the seven contact types of BENCHMARKS.md C (Keissar tables
// 3.1-3.6), invariance, EPA against brute-force SAT on random polyhedra, separated, touching, deep
// and degenerate pairs.
#include <gtest/gtest.h>

#include <cstdio>
#include <random>

#include "contact_test_util.h"
#include "polydem/contact/contact_cases.h"
#include "polydem/contact/gjk/gjk_epa.h"
#include "polydem/geometry/shapes.h"

namespace polydem::contact {
namespace {

using testing::CasePair;
using testing::overlapAlong;
using testing::placeCase;
using testing::Placed;
using testing::placeWorld;
using testing::randomRotation;
using testing::randomUnit;
using testing::satPenetration;

const GjkEpaKernel kEpa;
const GjkEpaIpmKernel kIpm;

ContactCase findCase(const std::string& id) {
  for (const auto& c : contactTypeCases()) {
    if (c.id == id) return c;
  }
  ADD_FAILURE() << "no case " << id;
  return {};
}

Contact resolve(const Kernel& k, const CasePair& p) {
  return k.collide(p.a->body(), p.b->body(), nullptr);
}

void print(const char* kernel, const ContactCase& c, const Contact& r) {
  const CaseEvaluation e = evaluate(c, r);
  std::printf(
      "%-12s %-6s normal (%+.6e %+.6e %+.6e) point (%+.6e %+.6e %+.6e) depth %.6e | "
      "normal err %.2e rad, point err %.2e, depth err %.2e%s\n",
      kernel, c.id.c_str(), r.normal.x(), r.normal.y(), r.normal.z(), r.point.x(), r.point.y(),
      r.point.z(), r.depth, e.normal_error_rad, e.point_error, e.depth_error,
      e.correct() ? "  correct" : "");
}

// Cases whose minimum-translation direction is the vertical: both kernels get normal and depth.
const char* const kVerticalMtd[] = {"C-VF", "C-EEx", "C-EF", "C-FF"};
// Cases whose minimum translation is inclined: an MTD method cannot return the vertical.
const char* const kInclinedMtd[] = {"C-VV", "C-VE", "C-EEp"};

TEST(GjkEpaCases, ReportAllSeven) {
  for (const auto& c : contactTypeCases()) {
    const CasePair p = placeCase(c);
    print("gjk-epa", c, resolve(kEpa, p));
    print("gjk-epa-ipm", c, resolve(kIpm, p));
    const auto sat = satPenetration(p.a->body(), p.b->body());
    std::printf("%-12s %-6s normal (%+.6e %+.6e %+.6e) depth %.6e (runner-up %.6e)\n", "SAT",
                c.id.c_str(), sat.normal.x(), sat.normal.y(), sat.normal.z(), sat.depth,
                sat.runner_up);
  }
}

TEST(GjkEpaCases, NormalAndDepthRightWhereTheMtdIsVertical) {
  for (const char* id : kVerticalMtd) {
    const ContactCase c = findCase(id);
    const CaseEvaluation e = evaluate(c, resolve(kEpa, placeCase(c)));
    EXPECT_TRUE(e.touching && e.normal_ok && e.depth_ok)
        << id << ": normal error " << e.normal_error_rad << " depth error " << e.depth_error;
  }
}

TEST(GjkEpaCases, BarycentricPointRightOnVertexFaceAndCrossingEdges) {
  // Keissar tables 3.3 and 3.5: one feature of A - B's closest face is a single point of A or B.
  for (const char* id : {"C-VF", "C-EEx"}) {
    const ContactCase c = findCase(id);
    EXPECT_TRUE(evaluate(c, resolve(kEpa, placeCase(c))).correct()) << id;
  }
}

TEST(GjkEpaCases, FaceFacePointIsOffCentreAndPoseDependent) {
  // Keissar section 2.2 and table 3.7: on parallel faces EPA's barycentric point lands off the
  // centre of the patch; which triangle of A - B holds it depends on the pose.
  const ContactCase c = findCase("C-FF");
  const CaseEvaluation e = evaluate(c, resolve(kEpa, placeCase(c)));
  EXPECT_TRUE(e.normal_ok && e.depth_ok);
  EXPECT_GT(e.point_error, 1e-3) << "EPA's point on C-FF is at the centre of the patch";
  std::mt19937_64 rng(7);
  double lo = 1e300, hi = 0.0;
  for (int i = 0; i < 20; ++i) {
    const Mat3 R = randomRotation(rng);
    const Vec3 t = 3.0 * randomUnit(rng);
    const ContactCase moved = transformed(c, R, t, 1.0);
    const CaseEvaluation m = evaluate(moved, resolve(kEpa, placeCase(c, R, t, 1.0)));
    EXPECT_TRUE(m.normal_ok && m.depth_ok);
    EXPECT_GT(m.point_error, 1e-3);
    lo = std::min(lo, m.point_error);
    hi = std::max(hi, m.point_error);
  }
  std::printf("gjk-epa C-FF point error over 20 poses: %.4f .. %.4f of the size\n", lo, hi);
  EXPECT_GT(hi - lo, 1e-3) << "the point error does not depend on the pose";
}

TEST(GjkEpaIpmCases, CorrectWhereTheMtdIsVertical) {
  for (const char* id : kVerticalMtd) {
    const ContactCase c = findCase(id);
    const Contact r = resolve(kIpm, placeCase(c));
    const CaseEvaluation e = evaluate(c, r);
    EXPECT_TRUE(e.correct()) << id << ": normal " << e.normal_error_rad << " point "
                             << e.point_error << " depth " << e.depth_error;
    EXPECT_EQ(r.status, Status::kOk) << id;
  }
}

TEST(GjkEpaCases, InclinedCasesGiveTheMinimumTranslation) {
  // Keissar tables 3.1, 3.2, 3.4: the normal is inclined. That is the minimum translation of A
  // out of B, which brute-force SAT finds too: right for an MTD method, wrong for the benchmark.
  for (const char* id : kInclinedMtd) {
    const ContactCase c = findCase(id);
    const CasePair p = placeCase(c);
    const auto sat = satPenetration(p.a->body(), p.b->body());
    for (const Kernel* k : {static_cast<const Kernel*>(&kEpa), static_cast<const Kernel*>(&kIpm)}) {
      const Contact r = resolve(*k, p);
      ASSERT_TRUE(r.touching) << id;
      EXPECT_NEAR(r.depth, sat.depth, 1e-12) << id;
      EXPECT_NEAR(overlapAlong(p.a->body(), p.b->body(), r.normal), sat.depth, 1e-12) << id;
      EXPECT_GT(angleBetween(r.normal, c.normal), 1e-3) << id << ": vertical after all";
    }
  }
}

void expectInvariant(const Kernel& k, const ContactCase& c, bool point_too) {
  std::mt19937_64 rng(11);
  for (double scale : {1.0, 1e-3, 1e3}) {
    for (int i = 0; i < 20; ++i) {
      const Mat3 R = i == 0 ? Mat3::Identity() : randomRotation(rng);
      const Vec3 t = i == 0 ? Vec3::Zero() : Vec3(scale * 5.0 * randomUnit(rng));
      const ContactCase moved = transformed(c, R, t, scale);
      const Contact r = k.collide(placeCase(c, R, t, scale).a->body(),
                                  placeCase(c, R, t, scale).b->body(), nullptr);
      const CaseEvaluation e = evaluate(moved, r);
      EXPECT_TRUE(e.touching && e.normal_ok && e.depth_ok && (!point_too || e.point_ok))
          << k.name() << " " << c.id << " scale " << scale << " pose " << i << ": normal "
          << e.normal_error_rad << " point " << e.point_error << " depth " << e.depth_error;
    }
  }
}

TEST(GjkEpaCases, InvariantUnderRigidMotionAndScale) {
  for (const char* id : kVerticalMtd) expectInvariant(kEpa, findCase(id), false);
  for (const char* id : {"C-VF", "C-EEx"}) expectInvariant(kEpa, findCase(id), true);
}

TEST(GjkEpaIpmCases, InvariantUnderRigidMotionAndScale) {
  for (const char* id : kVerticalMtd) expectInvariant(kIpm, findCase(id), true);
}

// Random pairs of random polyhedra (8-40 vertices), random poses, until 2000 overlap, shallow to
// deep: EPA's depth equals the SAT minimum and its normal is a direction achieving it; the
// separated ones are reported apart.
TEST(GjkEpaRandom, DepthAndNormalMatchBruteForceSat) {
  std::mt19937_64 rng(2024);
  std::uniform_int_distribution<int> count(8, 40);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  int overlapping = 0, separated = 0, unique_normals = 0;
  double worst_depth = 0.0, worst_angle = 0.0;
  for (int i = 0; i < 4000 && overlapping < 2000; ++i) {
    const Vec3 axes_a(0.5 + unit(rng), 0.5 + unit(rng), 0.5 + unit(rng));
    const Vec3 axes_b(0.5 + unit(rng), 0.5 + unit(rng), 0.5 + unit(rng));
    auto shape_a = geometry::ConvexPolyhedron::fromPoints(
        geometry::shapes::randomConvex(count(rng), rng(), axes_a, 0.2));
    auto shape_b = geometry::ConvexPolyhedron::fromPoints(
        geometry::shapes::randomConvex(count(rng), rng(), axes_b, 0.2));
    const double reach = shape_a.circumradius() + shape_b.circumradius();
    // Centre distances from 0 (deep) to 0.8 of the sum of circumradii (grazing or apart).
    const double distance = 0.8 * reach * std::pow(unit(rng), 0.5);
    const Vec3 where = 10.0 * Vec3(unit(rng), unit(rng), unit(rng));  // away from the origin
    const Placed a(std::move(shape_a), where + distance * randomUnit(rng), randomRotation(rng));
    const Placed b(std::move(shape_b), where, randomRotation(rng));
    const auto sat = satPenetration(a.body(), b.body());
    const double L = a.body().circumradius() + b.body().circumradius();
    particles::PairState state;
    const Contact r = kEpa.collide(a.body(), b.body(), &state);
    if (std::abs(sat.depth) < 1e-9 * L) continue;  // grazing: either answer is right
    ASSERT_EQ(r.touching, sat.depth > 0.0) << "pair " << i << " SAT depth " << sat.depth;
    if (!r.touching) {
      ++separated;
      continue;
    }
    ++overlapping;
    EXPECT_EQ(r.status, Status::kOk) << "pair " << i;
    EXPECT_NEAR(r.depth, sat.depth, 1e-9 * L) << "pair " << i;
    EXPECT_NEAR(overlapAlong(a.body(), b.body(), r.normal), sat.depth, 1e-9 * L) << "pair " << i;
    worst_depth = std::max(worst_depth, std::abs(r.depth - sat.depth) / L);
    if (sat.runner_up - sat.depth > 1e-9 * L) {
      ++unique_normals;
      const double angle = angleBetween(r.normal, sat.normal);
      EXPECT_LT(angle, 1e-9) << "pair " << i;
      worst_angle = std::max(worst_angle, angle);
    }
    // The warm start from this answer gives the same answer.
    const Contact again = kEpa.collide(a.body(), b.body(), &state);
    EXPECT_NEAR(again.depth, r.depth, 1e-9 * L) << "pair " << i;
  }
  std::printf(
      "random pairs: %d overlapping (%d with a unique normal), %d separated; worst depth error "
      "%.2e of the size, worst normal angle %.2e rad\n",
      overlapping, unique_normals, separated, worst_depth, worst_angle);
  EXPECT_EQ(overlapping, 2000);
  EXPECT_GT(separated, 500);
}

TEST(GjkEpaPairs, SeparatedPairsAreNotTouching) {
  const auto a = placeWorld(geometry::shapes::cube(1.0));
  for (const Vec3& gap : {Vec3(1.0 + 1e-9, 0.0, 0.0), Vec3(0.0, 0.0, -1.5), Vec3(2.0, 2.0, 2.0)}) {
    std::vector<Vec3> moved = geometry::shapes::cube(1.0);
    for (auto& v : moved) v += gap;
    const auto b = placeWorld(moved);
    particles::PairState state;
    for (const Kernel* k : {static_cast<const Kernel*>(&kEpa), static_cast<const Kernel*>(&kIpm)}) {
      EXPECT_FALSE(k->collide(a->body(), b->body(), nullptr).touching);
      EXPECT_FALSE(k->collide(a->body(), b->body(), &state).touching);
      EXPECT_FALSE(k->collide(a->body(), b->body(), &state).touching);  // warm
    }
    // The stored axis separates: A's lowest point along it is above B's highest.
    EXPECT_EQ(state.warm_valid, 1u);
    EXPECT_LT(overlapAlong(a->body(), b->body(), state.warm_direction), 0.0);
  }
}

TEST(GjkEpaPairs, FaceTouchingCubesAreNotTouching) {
  // Depth exactly 0: faces in contact, no overlap.
  const auto a = placeWorld(geometry::shapes::box({0, 0, 0}, {1, 1, 1}));
  const auto b = placeWorld(geometry::shapes::box({0.25, 0.5, -1}, {2, 3, 0}));
  EXPECT_FALSE(kEpa.collide(a->body(), b->body(), nullptr).touching);
  EXPECT_FALSE(kIpm.collide(a->body(), b->body(), nullptr).touching);
}

TEST(GjkEpaPairs, MillimetreCubesOverlappingByTenNanometres) {
  // libccd's absolute tolerances (1e-4 for EPA) are a tenth of this cube: it misses the contact.
  const double edge = 1e-3, overlap = 1e-8;
  const auto a = placeWorld(geometry::shapes::box({0, 0, edge - overlap}, {edge, edge, 2 * edge}));
  const auto b = placeWorld(geometry::shapes::box({0, 0, 0}, {edge, edge, edge}));
  for (const Kernel* k : {static_cast<const Kernel*>(&kEpa), static_cast<const Kernel*>(&kIpm)}) {
    const Contact r = k->collide(a->body(), b->body(), nullptr);
    ASSERT_TRUE(r.touching) << k->name();
    EXPECT_NEAR(r.depth, overlap, 1e-3 * overlap) << k->name();
    EXPECT_LT(angleBetween(r.normal, Vec3::UnitZ()), 1e-6) << k->name();
  }
  const Contact ipm = kIpm.collide(a->body(), b->body(), nullptr);
  EXPECT_LT((ipm.point - Vec3(0.5 * edge, 0.5 * edge, edge - 0.5 * overlap)).norm(), 1e-6 * edge);
}

TEST(GjkEpaPairs, IdenticalCoincidentBodies) {
  // A unit cube on itself: every axis of the cube needs a translation of 1.
  const auto a = placeWorld(geometry::shapes::cube(1.0));
  const auto b = placeWorld(geometry::shapes::cube(1.0));
  for (const Kernel* k : {static_cast<const Kernel*>(&kEpa), static_cast<const Kernel*>(&kIpm)}) {
    const Contact r = k->collide(a->body(), b->body(), nullptr);
    ASSERT_TRUE(r.touching);
    EXPECT_NEAR(r.depth, 1.0, 1e-12);
    EXPECT_NEAR(r.normal.cwiseAbs().maxCoeff(), 1.0, 1e-12);  // along an axis
  }
}

TEST(GjkEpaPairs, SmallBodyInsideALargeOne) {
  // A small cube deep inside a large one: it must move out through the nearest face.
  const auto a = placeWorld(geometry::shapes::box({0.1, 0.2, 0.3}, {0.3, 0.4, 0.5}));
  const auto b = placeWorld(geometry::shapes::box({-2, -2, -2}, {2, 2, 2}));
  for (const Kernel* k : {static_cast<const Kernel*>(&kEpa), static_cast<const Kernel*>(&kIpm)}) {
    const Contact r = k->collide(a->body(), b->body(), nullptr);
    ASSERT_TRUE(r.touching);
    EXPECT_NEAR(r.depth, 2.0 - 0.3, 1e-12);  // out through z = 2, the nearest face to its base
    EXPECT_LT(angleBetween(r.normal, Vec3::UnitZ()), 1e-9);
  }
}

TEST(GjkEpaPairs, LargePolyhedraUseTheHillClimb) {
  // More vertices than the scanning threshold: supports climb the vertex graph in the body frame.
  const geometry::ConvexPolyhedron round =
      geometry::ConvexPolyhedron::fromPoints(geometry::shapes::randomConvex(60, 5));
  std::mt19937_64 rng(3);
  for (int i = 0; i < 30; ++i) {
    const Placed a(round, 1.2 * randomUnit(rng), randomRotation(rng));
    const Placed b(round, Vec3::Zero(), randomRotation(rng));
    const auto sat = satPenetration(a.body(), b.body());
    const Contact r = kEpa.collide(a.body(), b.body(), nullptr);
    ASSERT_EQ(r.touching, sat.depth > 0.0);
    if (r.touching) {
      EXPECT_NEAR(r.depth, sat.depth, 1e-9);
    }
  }
}

}  // namespace
}  // namespace polydem::contact
