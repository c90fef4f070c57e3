// Kernels fcp and fcp-ipm: the seven contact types of BENCHMARKS.md C (Keissar tables 3.1-3.6),
// invariance under rigid motions and units, a tilted face-face contact, a hexagonal rod off the
// centre of a slope, separated, touching, tiny, coincident and nested bodies.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

#include "contact_test_util.h"
#include "polydem/contact/contact_cases.h"
#include "polydem/contact/fcp/fcp.h"
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

const FcpKernel kFcp;
const FcpIpmKernel kFcpIpm;
const Kernel* const kBoth[] = {&kFcp, &kFcpIpm};

ContactCase findCase(const std::string& id) {
  for (const auto& c : contactTypeCases()) {
    if (c.id == id) return c;
  }
  ADD_FAILURE() << "no case " << id;
  return {};
}

Contact resolve(const Kernel& k, const CasePair& p, particles::PairState* state = nullptr) {
  return k.collide(p.a->body(), p.b->body(), state);
}

void print(std::string_view kernel, const ContactCase& c, const Contact& r) {
  const CaseEvaluation e = evaluate(c, r);
  std::printf(
      "%-8s %-6s normal (%+.6e %+.6e %+.6e) point (%+.6e %+.6e %+.6e) depth %.6e | "
      "normal err %.2e rad, point err %.2e, depth err %.2e%s\n",
      std::string(kernel).c_str(), c.id.c_str(), r.normal.x(), r.normal.y(), r.normal.z(),
      r.point.x(), r.point.y(), r.point.z(), r.depth, e.normal_error_rad, e.point_error,
      e.depth_error, e.correct() ? "  correct" : "");
}

// Keissar section 3.3: FCP is right on these (the plane of largest gap is horizontal) ...
const char* const kRight[] = {"C-VF", "C-EEx", "C-EF", "C-FF"};
// ... and wrong on these: the plane of largest gap is a face of the inverted pyramid (VV), is
// tilted onto a face of a pyramid or prism (VE), or onto the cube's flank (EEp).
const char* const kWrong[] = {"C-VV", "C-VE", "C-EEp"};

TEST(FcpCases, ReportAllSeven) {
  for (const auto& c : contactTypeCases()) {
    for (const Kernel* k : kBoth) print(k->name(), c, resolve(*k, placeCase(c)));
  }
}

TEST(FcpCases, CorrectOnVertexFaceCrossingEdgesEdgeFaceAndFaceFace) {
  for (const char* id : kRight) {
    const ContactCase c = findCase(id);
    for (const Kernel* k : kBoth) {
      const Contact r = resolve(*k, placeCase(c));
      const CaseEvaluation e = evaluate(c, r);
      EXPECT_TRUE(e.correct()) << k->name() << " " << id << ": normal " << e.normal_error_rad
                               << " point " << e.point_error << " depth " << e.depth_error;
      EXPECT_EQ(r.status, Status::kOk) << k->name() << " " << id;
    }
  }
}

TEST(FcpCases, WrongCasesGiveTheTiltedPlaneOfLargestGap) {
  // Recorded, not the benchmark's answer: the normal is the brute-force SAT optimum, tilted.
  for (const char* id : kWrong) {
    const ContactCase c = findCase(id);
    const CasePair p = placeCase(c);
    const auto sat = satPenetration(p.a->body(), p.b->body());
    for (const Kernel* k : kBoth) {
      const Contact r = resolve(*k, p);
      ASSERT_TRUE(r.touching) << id;
      EXPECT_NEAR(r.depth, sat.depth, 1e-15) << id;
      EXPECT_NEAR(overlapAlong(p.a->body(), p.b->body(), r.normal), sat.depth, 1e-15) << id;
      const CaseEvaluation e = evaluate(c, r);
      std::printf("%-8s %-6s recorded: normal %.4f rad off, depth %.4e (analytical %.0e)\n",
                  std::string(k->name()).c_str(), id, e.normal_error_rad, r.depth, c.depth);
    }
  }
}

TEST(FcpCases, InvariantUnderRigidMotionAndScale) {
  std::mt19937_64 rng(17);
  for (const char* id : kRight) {
    const ContactCase c = findCase(id);
    for (double scale : {1.0, 1e-3, 1e3}) {
      for (int i = 0; i < 12; ++i) {
        const Mat3 R = i == 0 ? Mat3::Identity() : randomRotation(rng);
        const Vec3 t = i == 0 ? Vec3::Zero() : Vec3(scale * 5.0 * randomUnit(rng));
        const ContactCase m = transformed(c, R, t, scale);
        const CasePair p = placeCase(c, R, t, scale);
        for (const Kernel* k : kBoth) {
          particles::PairState state;
          const Contact cold = resolve(*k, p, &state);
          const Contact warm = resolve(*k, p, &state);
          for (const Contact& r : {cold, warm}) {
            const CaseEvaluation e = evaluate(m, r);
            EXPECT_TRUE(e.correct())
                << k->name() << " " << id << " scale " << scale << " pose " << i << ": normal "
                << e.normal_error_rad << " point " << e.point_error << " depth " << e.depth_error;
          }
        }
      }
    }
  }
}

TEST(FcpCases, TiltedFaceFaceContact) {
  // C-FF with the upper cube turned by theta about the y axis through the middle of its base.
  // fcp classifies the contact by the band of FcpTolerance::kBand (3.4e-9 here): face-face up to
  // a tilt of about 3e-9 rad, then the low edge, whose middle is 0.5 away. fcp-ipm follows the
  // polygon in which the mid-plane cuts the cube: its centroid moves continuously with theta.
  const ContactCase c = findCase("C-FF");
  const double g = c.depth;
  for (double theta : {0.0, 1e-9, 1e-7, 1e-5}) {
    const Mat3 R = Eigen::AngleAxisd(theta, Vec3::UnitY()).toRotationMatrix();
    const Vec3 pivot(0.0, 0.0, -g);
    std::vector<Vec3> a = c.a;
    for (Vec3& v : a) v = pivot + R * (v - pivot);
    const auto pa = placeWorld(a);
    const auto pb = placeWorld(c.b);
    const Contact f = kFcp.collide(pa->body(), pb->body(), nullptr);
    const Contact fi = kFcpIpm.collide(pa->body(), pb->body(), nullptr);
    // Expected mid-plane section: the cube where its tilted base lies below the mid-plane.
    const double level_a = -g - 0.5 * std::sin(theta);
    const double mid = 0.5 * level_a;
    const double cut = theta == 0.0 ? -0.5 : std::max(-0.5, -(mid + g) / std::sin(theta));
    const Vec3 ipm_expected(0.5 * (cut + 0.5) * std::cos(theta), 0.0, mid);
    std::printf(
        "C-FF tilted %.0e rad: fcp point (%+.6f %+.6f %+.3e) moved %.3e; fcp-ipm point (%+.6f "
        "%+.6f %+.3e) moved %.3e; depth %.4e\n",
        theta, f.point.x(), f.point.y(), f.point.z(), (f.point - c.point).norm(), fi.point.x(),
        fi.point.y(), fi.point.z(), (fi.point - c.point).norm(), f.depth);
    EXPECT_LT(angleBetween(f.normal, Vec3::UnitZ()), 1e-12);
    EXPECT_NEAR(f.depth, -level_a, 1e-15);
    EXPECT_LT((fi.point - ipm_expected).norm(), 1e-9) << theta;
    if (theta <= 1e-9) {
      EXPECT_LT((f.point - c.point).norm(), 1e-9) << theta;
    }
  }
}

TEST(FcpCases, HexagonalRodOffTheCentreOfASlope) {
  // Keissar fig. 3.7: a hexagonal rod, axis horizontal along x, on a 30 deg slope block, shifted
  // along its axis off the block's centre. On its edge (edge-face) and on its face (face-face) the
  // point must lie level with the rod's centroid along the axis, or the contact force twists it.
  const auto rod_shape = geometry::ConvexPolyhedron::fromPoints(
      geometry::shapes::prism({{-1.5, 0.5, 0.0},
                               {-1.5, 0.25, 0.433012701892219},
                               {-1.5, -0.25, 0.433012701892219},
                               {-1.5, -0.5, 0.0},
                               {-1.5, -0.25, -0.433012701892219},
                               {-1.5, 0.25, -0.433012701892219}},
                              Vec3(3.0, 0.0, 0.0)));
  const auto slope = geometry::ConvexPolyhedron::fromPoints(
      geometry::shapes::box({-4.0, -4.0, -2.0}, {4.0, 4.0, 0.0}));
  const Mat3 tilt = Eigen::AngleAxisd(degToRad(30.0), Vec3::UnitX()).toRotationMatrix();
  const Vec3 up = tilt * Vec3::UnitZ();
  for (double roll : {0.0, degToRad(30.0)}) {  // on an edge, on a face
    const Mat3 R = tilt * Eigen::AngleAxisd(roll, Vec3::UnitX()).toRotationMatrix();
    double lowest = 0.0;  // of the rod's corners along the slope's normal, rod frame at the origin
    for (const Vec3& v : rod_shape.vertices()) lowest = std::min(lowest, up.dot(R * v));
    // 1.3 along the axis and 0.4 across, off the block's centre; 1e-5 into the block.
    const Vec3 position = tilt * Vec3(1.3, 0.4, 0.0) - (lowest + 1e-5) * up;
    const Placed rod(rod_shape, position, R);
    const Placed block(slope, Vec3::Zero(), tilt);
    for (const Kernel* k : kBoth) {
      const Contact r = k->collide(rod.body(), block.body(), nullptr);
      ASSERT_TRUE(r.touching);
      EXPECT_LT(angleBetween(r.normal, up), 1e-12) << k->name();
      const Vec3 axis = R * Vec3::UnitX();
      EXPECT_NEAR(axis.dot(r.point - rod.body().centroid()), 0.0, 1e-9)
          << k->name() << " roll " << roll;
    }
  }
}

TEST(FcpPairs, SeparatedAndTouchingPairsAreNotTouching) {
  const auto a = placeWorld(geometry::shapes::cube(1.0));
  for (const Vec3& gap : {Vec3(1.0 + 1e-9, 0.0, 0.0), Vec3(0.0, 0.0, -1.5), Vec3(2.0, 2.0, 2.0),
                          Vec3(0.0, 0.0, 1.0)}) {  // the last one touches face to face
    std::vector<Vec3> moved = geometry::shapes::cube(1.0);
    for (auto& v : moved) v += gap;
    const auto b = placeWorld(moved);
    for (const Kernel* k : kBoth) {
      particles::PairState state;
      EXPECT_FALSE(k->collide(a->body(), b->body(), nullptr).touching);
      EXPECT_FALSE(k->collide(a->body(), b->body(), &state).touching);
      EXPECT_FALSE(k->collide(a->body(), b->body(), &state).touching);  // warm
    }
  }
}

TEST(FcpPairs, MillimetreCubesOverlappingByTenNanometres) {
  const double edge = 1e-3, overlap = 1e-8;
  const auto a = placeWorld(geometry::shapes::box({0, 0, edge - overlap}, {edge, edge, 2 * edge}));
  const auto b =
      placeWorld(geometry::shapes::box({0.2 * edge, -0.3 * edge, 0}, {edge, edge, edge}));
  // The patch is x in [0.2, 1], y in [0, 1] mm.
  const Vec3 expected(0.6 * edge, 0.5 * edge, edge - 0.5 * overlap);
  for (const Kernel* k : kBoth) {
    const Contact r = k->collide(a->body(), b->body(), nullptr);
    ASSERT_TRUE(r.touching) << k->name();
    EXPECT_NEAR(r.depth, overlap, 1e-9 * overlap) << k->name();
    EXPECT_LT(angleBetween(r.normal, Vec3::UnitZ()), 1e-12) << k->name();
    EXPECT_LT((r.point - expected).norm(), 1e-9 * edge) << k->name();
  }
}

TEST(FcpPairs, IdenticalCoincidentBodies) {
  // A unit cube on itself: every axis needs a translation of 1; the point is the cube's centre.
  const auto a = placeWorld(geometry::shapes::cube(1.0));
  const auto b = placeWorld(geometry::shapes::cube(1.0));
  for (const Kernel* k : kBoth) {
    const Contact r = k->collide(a->body(), b->body(), nullptr);
    ASSERT_TRUE(r.touching);
    EXPECT_NEAR(r.depth, 1.0, 1e-12);
    EXPECT_NEAR(r.normal.cwiseAbs().maxCoeff(), 1.0, 1e-12);
    EXPECT_LT(r.point.norm(), 1e-12) << k->name();
  }
}

TEST(FcpPairs, SmallBodyInsideALargeOne) {
  // Out through the nearest face: z = 2, 1.7 above the small cube's base.
  const auto a = placeWorld(geometry::shapes::box({0.1, 0.2, 0.3}, {0.3, 0.4, 0.5}));
  const auto b = placeWorld(geometry::shapes::box({-2, -2, -2}, {2, 2, 2}));
  for (const Kernel* k : kBoth) {
    const Contact r = k->collide(a->body(), b->body(), nullptr);
    ASSERT_TRUE(r.touching);
    EXPECT_NEAR(r.depth, 2.0 - 0.3, 1e-12);
    EXPECT_LT(angleBetween(r.normal, Vec3::UnitZ()), 1e-12);
    EXPECT_LT((r.point - Vec3(0.2, 0.3, 0.3 + 0.5 * r.depth)).norm(), 1e-12) << k->name();
  }
}

TEST(FcpPairs, RegistryKnowsBothKernels) {
  EXPECT_EQ(makeKernel("fcp")->name(), "fcp");
  EXPECT_EQ(makeKernel("fcp-ipm")->name(), "fcp-ipm");
}

}  // namespace
}  // namespace polydem::contact
