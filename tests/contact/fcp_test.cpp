// FCP search: the common plane against brute-force separating-axis references.
#include <gtest/gtest.h>

#include <cstdio>

#include "contact/fcp.h"
#include "fcp_reference.h"
#include "geometry/shapes.h"

namespace polydem::contact {
namespace {

using testing::bruteForceSat;
using testing::Placed;
using testing::randomRotation;
using testing::randomUnit;

std::vector<geometry::ConvexPolyhedron> randomShapes(int count, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_int_distribution<int> vertices(8, 40);
  std::uniform_real_distribution<double> axis(0.4, 1.5);
  std::vector<geometry::ConvexPolyhedron> shapes;
  for (int i = 0; i < count; ++i) {
    const Vec3 semi(axis(rng), axis(rng), axis(rng));
    shapes.push_back(geometry::ConvexPolyhedron::fromPoints(
        geometry::shapes::randomConvex(vertices(rng), seed * 1000 + i, semi, 0.2)));
  }
  return shapes;
}

struct Tally {
  int pairs = 0, certified = 0, full_scan = 0, improved = 0, moves = 0;
  void add(const FcpTrace& t) {
    ++pairs;
    certified += t.certified;
    full_scan += t.full_scan;
    improved += t.full_scan_improved;
    moves += t.moves;
  }
  void print(const char* what) const {
    std::printf(
        "[fcp] %s: %d pairs, certified %d, full scan %d (improved on the local search %d),"
        " mean moves %.2f\n",
        what, pairs, certified, full_scan, improved,
        pairs ? static_cast<double>(moves) / pairs : 0.0);
  }
};

TEST(FcpSearch, OverlapGapIsTheBruteForceSatOptimum) {
  const auto shapes = randomShapes(40, 7);
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  Tally deep, shallow;
  for (int k = 0; k < 2000; ++k) {
    const auto& sa = shapes[k % shapes.size()];
    const auto& sb = shapes[(k * 7 + 3) % shapes.size()];
    Placed b(sb, Vec3::Zero(), randomRotation(rng));
    Placed a(sa, Vec3::Zero(), randomRotation(rng));
    const Vec3 u = randomUnit(rng);
    const double scale = sa.circumradius() + sb.circumradius();
    const bool is_shallow = k % 2 == 0;
    // Deep: anywhere inside. Shallow: pushed against B along the brute-force normal until the
    // largest gap is about -1e-3 of the size (DEM-like contacts).
    a = Placed(sa, u * scale * unit(rng), a.body.rotation);
    if (is_shallow) {
      a = Placed(sa, 3.0 * scale * u, a.body.rotation);
      for (int i = 0; i < 20; ++i) {
        const auto r = bruteForceSat(a.body, b.body);
        if (r.gap < -0.5e-3 * scale) break;
        a = Placed(sa, a.body.position - (r.gap + 1e-3 * scale) * r.normal, a.body.rotation);
      }
    }
    const auto ref = bruteForceSat(a.body, b.body);
    if (ref.gap >= 0.0) continue;
    FcpTrace trace;
    const CommonPlane cp = findCommonPlane(a.body, b.body, nullptr, {}, &trace);
    (is_shallow ? shallow : deep).add(trace);
    EXPECT_NEAR(cp.gap, ref.gap, 1e-9 * scale) << "pair " << k;
    EXPECT_NEAR(cp.gap, testing::scanGap(a.body, b.body, cp.normal), 1e-12 * scale);
    EXPECT_NEAR(cp.normal.norm(), 1.0, 1e-14);
  }
  deep.print("deep overlaps, cold");
  shallow.print("shallow overlaps, cold");
}

}  // namespace
}  // namespace polydem::contact
