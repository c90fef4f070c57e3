// The FCP's common plane on random polyhedra (8-40 vertices) against brute-force references:
// overlapping pairs (deep and shallow), separated pairs, warm starts along small rigid motions.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

#include "contact_test_util.h"
#include "fcp_reference.h"
#include "polydem/contact/fcp/fcp.h"
#include "polydem/geometry/shapes.h"

namespace polydem::contact {
namespace {

using testing::bruteForceCommonPlane;
using testing::overlapAlong;
using testing::Placed;
using testing::randomRotation;
using testing::randomUnit;
using testing::satPenetration;

/// How the searches went, printed for the report.
struct Tally {
  int pairs = 0, warm = 0, certified = 0, full_scan = 0, improved = 0, moves = 0;
  void add(const FcpTrace& t) {
    ++pairs;
    warm += t.warm;
    certified += t.certified;
    full_scan += t.full_scan;
    improved += t.full_scan_improved;
    moves += t.moves;
  }
  void print(const char* what) const {
    std::printf(
        "[fcp] %-28s %5d pairs: certified %5d, full scan %4d (%.2f%%; it beat the searched plane "
        "in %d), mean moves %.2f\n",
        what, pairs, certified, full_scan, pairs ? 100.0 * full_scan / pairs : 0.0, improved,
        pairs ? static_cast<double>(moves) / pairs : 0.0);
  }
};

std::unique_ptr<Placed> randomBody(std::mt19937_64& rng, const Vec3& position) {
  std::uniform_int_distribution<int> count(8, 40);
  std::uniform_real_distribution<double> axis(0.5, 1.5);
  const Vec3 semi(axis(rng), axis(rng), axis(rng));
  return std::make_unique<Placed>(geometry::ConvexPolyhedron::fromPoints(
                                      geometry::shapes::randomConvex(count(rng), rng(), semi, 0.2)),
                                  position, randomRotation(rng));
}

/// A moved copy of `p` (same shape, new pose).
std::unique_ptr<Placed> moved(const Placed& p, const Vec3& position, const Mat3& rotation) {
  return std::make_unique<Placed>(p.shape(), position, rotation);
}

/// Pushes A against B along the common plane's normal until the penetration is about `depth`
/// (a DEM-like shallow contact; the tests check the result against brute-force SAT).
std::unique_ptr<Placed> pushedIn(const Placed& a, const Placed& b, double depth) {
  FcpOptions exact;
  exact.stop_when_separated = false;
  auto out = moved(a, a.body().position, a.body().rotation);
  for (int i = 0; i < 30; ++i) {
    const CommonPlane cp = findCommonPlane(out->body(), b.body(), nullptr, exact);
    if (-cp.gap > 0.5 * depth) break;
    out = moved(*out, out->body().position - (depth + cp.gap) * cp.normal, out->body().rotation);
  }
  return out;
}

/// The common plane of an overlapping pair against brute-force SAT: the same gap, and the same
/// normal where SAT's minimum is unique.
void expectSatOptimum(const Placed& a, const Placed& b, const CommonPlane& cp, int pair) {
  const auto sat = satPenetration(a.body(), b.body());
  const double L = a.body().circumradius() + b.body().circumradius();
  EXPECT_NEAR(cp.gap, -sat.depth, 1e-9 * L) << "pair " << pair;
  EXPECT_NEAR(cp.gap, -overlapAlong(a.body(), b.body(), cp.normal), 1e-12 * L) << "pair " << pair;
  EXPECT_NEAR(cp.normal.norm(), 1.0, 1e-14);
  if (sat.runner_up - sat.depth > 1e-9 * L) {
    EXPECT_LT(angleBetween(cp.normal, sat.normal), 1e-9) << "pair " << pair;
  }
}

TEST(FcpSearch, OverlapGapAndNormalAreTheBruteForceSatOptimum) {
  std::mt19937_64 rng(2004);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  Tally deep, deep_searched, shallow;
  FcpOptions searched;
  searched.always_search = true;
  for (int i = 0; i < 1000; ++i) {
    const auto b = randomBody(rng, Vec3(3.0, -2.0, 7.0));
    auto a = randomBody(rng, Vec3::Zero());
    const Vec3 u = randomUnit(rng);
    const double L = a->body().circumradius() + b->body().circumradius();
    const bool is_shallow = i % 2 == 1;
    // Deep: centres anywhere within 0.7 L; shallow: pushed in by 1e-3 L from outside.
    a = moved(*a, b->body().position + (is_shallow ? 2.0 : 0.7 * unit(rng)) * L * u,
              a->body().rotation);
    if (is_shallow) a = pushedIn(*a, *b, 1e-3 * L);
    if (satPenetration(a->body(), b->body()).depth <= 1e-9 * L) continue;
    FcpTrace trace;
    const CommonPlane cp = findCommonPlane(a->body(), b->body(), nullptr, {}, &trace);
    (is_shallow ? shallow : deep).add(trace);
    expectSatOptimum(*a, *b, cp, i);
    if (!is_shallow) {
      // The local search run to its end before any scan: where it stalls, the scan must fix it.
      const CommonPlane cs = findCommonPlane(a->body(), b->body(), nullptr, searched, &trace);
      deep_searched.add(trace);
      expectSatOptimum(*a, *b, cs, i);
    }
  }
  deep.print("deep overlaps, cold:");
  deep_searched.print("deep, local search first:");
  shallow.print("shallow overlaps, cold:");
  EXPECT_GT(deep.pairs, 400);
  EXPECT_GT(shallow.pairs, 400);
  EXPECT_GT(deep_searched.improved, 0) << "the local search never stalled: the scan is untested";
}

TEST(FcpSearch, SeparatedPairsAreProvenApartAndTheirPlaneIsTheLargestGap) {
  std::mt19937_64 rng(1988);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  Tally tally;
  FcpOptions exact;
  exact.stop_when_separated = false;
  const FcpKernel fcp;
  int separated = 0;
  for (int i = 0; i < 600; ++i) {
    const auto b = randomBody(rng, Vec3(-1.0, 4.0, 2.0));
    auto a = randomBody(rng, Vec3::Zero());
    const double L = a->body().circumradius() + b->body().circumradius();
    a = moved(*a, b->body().position + (0.55 + 0.5 * unit(rng)) * L * randomUnit(rng),
              a->body().rotation);
    const auto ref = bruteForceCommonPlane(a->body(), b->body());
    if (ref.gap <= 1e-9 * L) continue;
    ++separated;
    // collide() stops at the first positive gap.
    particles::PairState state;
    EXPECT_FALSE(fcp.collide(a->body(), b->body(), &state).touching) << "pair " << i;
    EXPECT_FALSE(fcp.collide(a->body(), b->body(), &state).touching) << "pair " << i;
    const CommonPlane quick = findCommonPlane(a->body(), b->body(), nullptr);
    EXPECT_GT(quick.gap, 0.0);
    EXPECT_NEAR(quick.gap, -overlapAlong(a->body(), b->body(), quick.normal), 1e-12 * L);
    // Run to the end: the largest gap over the candidates.
    FcpTrace trace;
    const CommonPlane cp = findCommonPlane(a->body(), b->body(), nullptr, exact, &trace);
    tally.add(trace);
    EXPECT_FALSE(cp.separated_early);
    EXPECT_NEAR(cp.gap, ref.gap, 1e-9 * L) << "pair " << i;
    EXPECT_NEAR(cp.gap, -overlapAlong(a->body(), b->body(), cp.normal), 1e-12 * L);
  }
  tally.print("separated, to the largest gap:");
  EXPECT_GT(separated, 300);
}

TEST(FcpSearch, WarmStartAlongSmallMotionsGivesTheColdAnswer) {
  // A persistent contact: A creeps over B in small rigid steps; each step starts from the last
  // step's plane. The answer must be the cold one, and mostly cheap (certified after one move).
  std::mt19937_64 rng(31);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  Tally warm, cold;
  for (int pair = 0; pair < 40; ++pair) {
    const auto b = randomBody(rng, Vec3(0.5, 0.5, 0.5));
    auto a = randomBody(rng, Vec3::Zero());
    const double L = a->body().circumradius() + b->body().circumradius();
    a = pushedIn(*moved(*a, b->body().position + 2.0 * L * randomUnit(rng), a->body().rotation), *b,
                 2e-3 * L);
    const Vec3 drift = 1e-4 * L * randomUnit(rng);
    const Vec3 spin_axis = randomUnit(rng);
    Vec3 normal = findCommonPlane(a->body(), b->body(), nullptr).normal;
    for (int step = 0; step < 20; ++step) {
      const Mat3 turn = Eigen::AngleAxisd(2e-4 * unit(rng), spin_axis).toRotationMatrix();
      a = moved(*a, a->body().position + drift, turn * a->body().rotation);
      FcpTrace tw, tc;
      const CommonPlane w = findCommonPlane(a->body(), b->body(), &normal, {}, &tw);
      const CommonPlane c = findCommonPlane(a->body(), b->body(), nullptr, {}, &tc);
      warm.add(tw);
      cold.add(tc);
      // Separated pairs stop at the first positive gap, which depends on the start.
      if (c.gap < 0.0) {
        EXPECT_NEAR(w.gap, c.gap, 1e-12 * L) << "pair " << pair << " step " << step;
        expectSatOptimum(*a, *b, w, pair);
      } else {
        EXPECT_GT(w.gap, 0.0) << "pair " << pair << " step " << step;
      }
      normal = w.normal;
    }
  }
  warm.print("creeping contacts, warm:");
  cold.print("creeping contacts, cold:");
  EXPECT_GT(warm.certified, warm.pairs / 2);
}

TEST(FcpSearch, LargePolyhedraClimbTheVertexGraph) {
  // More vertices than a scan is worth: supports and bands walk the vertex graph.
  std::mt19937_64 rng(5);
  const geometry::ConvexPolyhedron round =
      geometry::ConvexPolyhedron::fromPoints(geometry::shapes::randomConvex(80, 9));
  for (int i = 0; i < 12; ++i) {
    const Placed a(round, 1.6 * randomUnit(rng), randomRotation(rng));
    const Placed b(round, Vec3::Zero(), randomRotation(rng));
    const CommonPlane cp = findCommonPlane(a.body(), b.body(), nullptr);
    if (cp.gap < 0.0) expectSatOptimum(a, b, cp, i);
  }
}

}  // namespace
}  // namespace polydem::contact
