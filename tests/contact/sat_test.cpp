// The separating-axis test (contact/sat/sat.h) against EPA and against the brute-force SAT of the
// test helpers on random pairs of small shapes; the warm axis; and gjk-epa-ipm, which uses it.
#include <gtest/gtest.h>

#include <bit>
#include <cstdint>
#include <cstdio>
#include <random>
#include <string>

#include "contact_test_util.h"
#include "polydem/contact/contact_cases.h"
#include "polydem/contact/gjk/gjk_epa.h"
#include "polydem/contact/sat/sat.h"
#include "polydem/contact/sat/sat_detail.h"
#include "polydem/geometry/shapes.h"

namespace polydem::contact {
namespace {

using testing::overlapAlong;
using testing::Placed;
using testing::randomRotation;
using testing::randomUnit;

namespace shapes = geometry::shapes;

// The small shapes the test uses: a cube, a tetrahedron, a triangular prism, a flat box.
geometry::ConvexPolyhedron smallShape(int kind, double size) {
  switch (kind % 4) {
    case 0:
      return geometry::ConvexPolyhedron::fromPoints(shapes::cube(size));
    case 1:
      return geometry::ConvexPolyhedron::fromPoints(shapes::tetrahedron(1.3 * size));
    case 2:
      return geometry::ConvexPolyhedron::fromPoints(shapes::prism(
          {Vec3(0, 0, 0), Vec3(size, 0, 0), Vec3(0.3 * size, 0.8 * size, 0)}, Vec3(0, 0, size)));
    default:
      return geometry::ConvexPolyhedron::fromPoints(
          shapes::box(Vec3::Zero(), Vec3(size, 0.6 * size, 0.3 * size)));
  }
}

TEST(Sat, AxesOfACubeAndATetrahedron) {
  const auto cube = geometry::ConvexPolyhedron::fromPoints(shapes::cube(1.0));
  EXPECT_EQ(cube.axisFaces().size(), 3u);
  EXPECT_EQ(cube.axisEdges().size(), 3u);
  const auto tet = geometry::ConvexPolyhedron::fromPoints(shapes::tetrahedron(1.0));
  EXPECT_EQ(tet.axisFaces().size(), 4u);
  EXPECT_EQ(tet.axisEdges().size(), 6u);
  const Placed a(cube, Vec3::Zero(), Mat3::Identity()), b(cube, Vec3::UnitX(), Mat3::Identity());
  EXPECT_TRUE(satApplies(a.body(), b.body()));  // 15 axes of 16 vertices
  const Placed big(geometry::ConvexPolyhedron::fromPoints(shapes::randomConvex(20, 7)),
                   Vec3::Zero(), Mat3::Identity());
  EXPECT_FALSE(satApplies(big.body(), b.body()));
}

// Random pairs from deep to apart, at scales 1e-3, 1 and 1e3: the separating-axis test finds
// the pair apart exactly where EPA does, and otherwise EPA's depth within its tolerance (the
// contact_gjk_epa bound, 1e-9 of the pair's size), a direction whose overlap (1) is that depth,
// and EPA's direction wherever the minimum is unique.
TEST(Sat, AgreesWithEpaOnRandomPairs) {
  std::mt19937_64 rng(2026);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  int overlapping = 0, separated = 0, unique_normals = 0, edge_axes = 0;
  double worst_depth = 0.0, worst_angle = 0.0;
  for (int i = 0; i < 6000; ++i) {
    const double scale = i % 3 == 0 ? 1e-3 : (i % 3 == 1 ? 1.0 : 1e3);
    auto shape_a = smallShape(static_cast<int>(rng() % 4), scale);
    auto shape_b = smallShape(static_cast<int>(rng() % 4), scale * (0.5 + unit(rng)));
    const double reach = shape_a.circumradius() + shape_b.circumradius();
    const double distance = 0.9 * reach * std::pow(unit(rng), 0.5);
    const Vec3 where = 10.0 * scale * Vec3(unit(rng), unit(rng), unit(rng));
    // Every fourth pair keeps both shapes aligned: ties between face and edge axes.
    const bool aligned = i % 4 == 3;
    const Placed a(std::move(shape_a), where + distance * randomUnit(rng),
                   aligned ? Mat3::Identity() : randomRotation(rng));
    const Placed b(std::move(shape_b), where, aligned ? Mat3::Identity() : randomRotation(rng));
    const double L = a.body().circumradius() + b.body().circumradius();
    ASSERT_TRUE(satApplies(a.body(), b.body()));
    const AxisTest sat = separatingAxisTest(a.body(), b.body(), nullptr, 1e-12 * L);
    const auto reference = testing::satPenetration(a.body(), b.body());
    particles::PairState state;
    const Contact epa = gjkEpaContact(a.body(), b.body(), &state);
    if (std::abs(reference.depth) < 1e-9 * L) continue;  // grazing: either answer is right
    ASSERT_EQ(sat.separated, !epa.touching) << "pair " << i << " depth " << reference.depth;
    if (sat.separated) {
      ++separated;
      EXPECT_LE(overlapAlong(a.body(), b.body(), sat.normal), 0.0) << "pair " << i;
      continue;
    }
    ++overlapping;
    edge_axes += sat.axis == AxisTest::Axis::kEdges;
    if (sat.axis == AxisTest::Axis::kEdges) {
      EXPECT_TRUE(crossingPoint(a.body(), b.body(), sat).allFinite()) << "pair " << i;
    }
    EXPECT_NEAR(sat.depth, epa.depth, 1e-9 * L) << "pair " << i;
    EXPECT_NEAR(sat.depth, reference.depth, 1e-9 * L) << "pair " << i;
    EXPECT_NEAR(overlapAlong(a.body(), b.body(), sat.normal), sat.depth, 1e-12 * L) << "pair " << i;
    EXPECT_NEAR(sat.normal.norm(), 1.0, 1e-14);
    worst_depth = std::max(worst_depth, std::abs(sat.depth - epa.depth) / L);
    if (reference.runner_up - reference.depth > 1e-9 * L) {
      ++unique_normals;
      const double angle = angleBetween(sat.normal, epa.normal);
      EXPECT_LT(angle, 1e-6) << "pair " << i;
      worst_angle = std::max(worst_angle, angle);
      // Crossing edges of random shapes: EPA's barycentric point is the middle of the edges'
      // closest points, and so is crossingPoint().
      if (sat.axis == AxisTest::Axis::kEdges && !aligned) {
        EXPECT_LT((crossingPoint(a.body(), b.body(), sat) - epa.point).norm(), 1e-9 * L)
            << "pair " << i;
      }
    }
    // The features: A's lowest and B's highest vertex along the normal span the depth.
    EXPECT_NEAR(sat.normal.dot(b.body().vertices[sat.highest_b] - a.body().vertices[sat.lowest_a]),
                sat.depth, 1e-12 * L)
        << "pair " << i;
  }
  std::printf(
      "SAT vs EPA: %d overlapping (%d with a unique normal, %d on an edge-edge axis), %d "
      "apart; worst depth difference %.2e of the size, worst angle %.2e rad\n",
      overlapping, unique_normals, edge_axes, separated, worst_depth, worst_angle);
  EXPECT_GT(overlapping, 2000);
  EXPECT_GT(separated, 500);
  EXPECT_GT(unique_normals, 1000);
  EXPECT_GT(edge_axes, 50);  // the edge-edge axes are exercised too
}

// Separated pairs are found so from any warm axis, and a separating warm axis is returned as is.
TEST(Sat, WarmAxis) {
  std::mt19937_64 rng(3);
  const auto cube = geometry::ConvexPolyhedron::fromPoints(shapes::cube(1.0));
  const Placed a(cube, Vec3(1.2, 0.1, 0.0), randomRotation(rng));
  const Placed b(cube, Vec3::Zero(), Mat3::Identity());
  const AxisTest cold = separatingAxisTest(a.body(), b.body(), nullptr, 1e-12);
  ASSERT_FALSE(cold.separated);
  const Vec3 wrong = -Vec3::UnitX();  // does not separate: the full test runs
  const AxisTest warm = separatingAxisTest(a.body(), b.body(), &wrong, 1e-12);
  EXPECT_EQ(warm.normal, cold.normal);
  EXPECT_EQ(warm.depth, cold.depth);
  const Placed apart(cube, Vec3(3.0, 0.0, 0.0), Mat3::Identity());
  const Vec3 axis = Vec3(1.0, 0.2, 0.0).normalized();
  const AxisTest kept = separatingAxisTest(apart.body(), b.body(), &axis, 1e-12);
  EXPECT_TRUE(kept.separated);
  EXPECT_EQ(kept.normal, axis);
  const AxisTest found = separatingAxisTest(apart.body(), b.body(), &wrong, 1e-12);
  EXPECT_TRUE(found.separated);
  EXPECT_LT(overlapAlong(apart.body(), b.body(), found.normal), 0.0);
}

// Two aligned cubes overlapping on a face, an edge and a corner: the answer is a face axis (the
// edge axes that coincide with it must not win by round-off), so gjk-epa-ipm skips EPA on them.
TEST(Sat, AlignedCubesGiveFaceAxes) {
  const auto cube = geometry::ConvexPolyhedron::fromPoints(shapes::cube(1.0));
  const Placed b(cube, Vec3::Zero(), Mat3::Identity());
  for (const Vec3& offset : {Vec3(0.999, 0, 0), Vec3(0.999, 0.999, 0), Vec3(0.999, 0.999, 0.999),
                             Vec3(0.3, 0.2, 0.999)}) {
    const Placed a(cube, offset, Mat3::Identity());
    const AxisTest sat = separatingAxisTest(a.body(), b.body(), nullptr, 1e-12 * 2 * 0.866);
    ASSERT_FALSE(sat.separated);
    EXPECT_NE(sat.axis, AxisTest::Axis::kEdges) << offset.transpose();
    EXPECT_NEAR(sat.depth, 0.001, 1e-12) << offset.transpose();
    particles::PairState state;
    const GjkEpaIpmKernel kernel;
    const Contact c = kernel.collideForSubContacts(a.body(), b.body(), &state);
    EXPECT_TRUE(c.touching);
    EXPECT_EQ(c.normal, sat.normal);
    EXPECT_EQ(c.depth, sat.depth);
    EXPECT_EQ(state.warm_direction, sat.normal);
  }
}

// Two parallelepipeds screen their edge axes by a bound (sat_box.cpp) and test only a few exactly:
// the answer must be the full test's, every field bit for bit. Two rectangular boxes take the
// classical test from their rotations (sat_obb.cpp), whose answer is the full test's up to
// round-off (agreement() below). Random pairs at three scales and positions far from the origin,
// and the degenerate cases of a dense pack: aligned and nearly aligned boxes (relative rotations of
// 1e-9 to 1e-3 rad) overlapping by a hair, touching or just apart on a face, an edge or a corner,
// boxes of different sizes, with and without a warm axis.
std::string differences(const AxisTest& fast, const AxisTest& full) {
  const auto bits = [](double x) { return std::bit_cast<std::uint64_t>(x); };
  std::string out;
  if (fast.separated != full.separated) out += " separated";
  for (int c = 0; c < 3; ++c) {
    if (bits(fast.normal[c]) != bits(full.normal[c])) out += " normal[" + std::to_string(c) + "]";
  }
  if (bits(fast.depth) != bits(full.depth)) out += " depth";
  if (fast.axis != full.axis) out += " axis";
  if (fast.feature_a != full.feature_a || fast.feature_b != full.feature_b) out += " features";
  if (fast.lowest_a != full.lowest_a || fast.highest_b != full.highest_b) out += " extremes";
  return out;
}

struct Agreement {
  int compared = 0, tied = 0, apart_near_touching = 0;
  double worst_depth = 0.0, worst_angle = 0.0;  // depth / tau; rad, where not tied
};

// The classical test against the full one, within tau = kDepth times the pair's size and kAngle:
// `separated` the same unless the overlapping answer is within tau of touching; apart, the normal
// separates the bodies within tau; otherwise the depths within tau, the normal's overlap (vertex by
// vertex) its depth within tau, the same axis and features unless the two answers tie within tau
// (then both depths agree, above, and the full test's normal has its depth too), the normals within
// kAngle where they do not tie, and the extreme vertices as low (as high) along the normal within
// tau.
constexpr double kAngle = 1e-12;
constexpr double kUnitRoundoff = 0x1p-53;
constexpr double kDepth = 1e-12;  // of the pair's size (the sum of the circumradii)

std::string agreement(const Body& a, const Body& b, const AxisTest& fast, const AxisTest& full,
                      double size, Agreement& s) {
  const double tau = kDepth * size;
  ++s.compared;
  std::string out;
  if (fast.separated != full.separated) {
    const AxisTest& overlapping = fast.separated ? full : fast;
    if (!(overlapping.depth <= tau)) out += " separated";
    ++s.apart_near_touching;
    return out;
  }
  if (fast.separated) {
    if (!(overlapAlong(a, b, fast.normal) <= tau)) out += " separating normal";
    return out;
  }
  const double miss = std::abs(fast.depth - full.depth);
  s.worst_depth = std::max(s.worst_depth, miss / tau);
  if (!(miss <= tau)) out += " depth";
  if (!(std::abs(overlapAlong(a, b, fast.normal) - fast.depth) <= tau)) out += " normal's overlap";
  const bool same = fast.axis == full.axis && fast.feature_a == full.feature_a &&
                    fast.feature_b == full.feature_b;
  if (!same) {
    ++s.tied;
    if (!(std::abs(overlapAlong(a, b, full.normal) - fast.depth) <= tau)) out += " tie";
  } else {
    // The direction of an edge axis e x f is known to within the round-off of the edges over
    // |e x f|: about u (1 + C / size) / sin(e, f) for the full test, whose edges are differences of
    // world vertices at C from the origin, and u / sin(e, f) for the classical test, whose axes
    // are rotated unit vectors; 1e-12 rad where the edges are not nearly parallel.
    double allowed = kAngle;
    if (fast.axis == AxisTest::Axis::kEdges) {
      const auto direction = [](const Body& body, int e) {
        const auto& edge = body.shape->edges()[e];
        return Vec3(body.vertices[edge.v1] - body.vertices[edge.v0]).normalized();
      };
      const double sine = direction(a, fast.feature_a).cross(direction(b, fast.feature_b)).norm();
      const double far = std::max(a.position.norm(), b.position.norm()) / size;
      allowed += 16.0 * kUnitRoundoff * (1.0 + far) / sine;
    }
    const double angle = angleBetween(fast.normal, full.normal);
    s.worst_angle = std::max(s.worst_angle, angle / allowed);
    if (!(angle <= allowed)) out += " normal";
  }
  // Extreme vertices: as low (as high) along the normal as any vertex, within tau. (The full
  // test's may be another corner of the same face where the normals tie.)
  const Vec3& n = fast.normal;
  double lowest = n.dot(a.vertices[0]), highest = n.dot(b.vertices[0]);
  for (const Vec3& x : a.vertices) lowest = std::min(lowest, n.dot(x));
  for (const Vec3& x : b.vertices) highest = std::max(highest, n.dot(x));
  if (!(n.dot(a.vertices[fast.lowest_a]) - lowest <= tau) ||
      !(highest - n.dot(b.vertices[fast.highest_b]) <= tau)) {
    out += " extremes";
  }
  return out;
}

// A box of sides sx, sy, sz, sheared by `shear` (0: a rectangular box; else a parallelepiped whose
// edges are not orthogonal, which the screen treats the same way).
geometry::ConvexPolyhedron boxShape(double sx, double sy, double sz, double shear = 0.0) {
  if (shear == 0.0) {
    return geometry::ConvexPolyhedron::fromPoints(shapes::box(Vec3::Zero(), Vec3(sx, sy, sz)));
  }
  const Vec3 a(sx, 0, 0), b(shear * sx, sy, 0), c(shear * sx, -shear * sy, sz);
  std::vector<Vec3> corners;
  for (int i = 0; i < 8; ++i) corners.push_back((i & 1) * a + (i >> 1 & 1) * b + (i >> 2) * c);
  return geometry::ConvexPolyhedron::fromPoints(corners);
}

Mat3 turn(const Vec3& axis, double angle) {
  return Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix();
}

TEST(Sat, BoxTestsGiveTheFullTestsAnswer) {
  std::mt19937_64 rng(15);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  int pairs = 0, apart = 0, on_edges = 0, on_faces = 0, bitwise = 0;
  Agreement boxes;
  const auto check = [&](const Placed& a, const Placed& b, const Vec3* warm, const char* what) {
    const double size = a.body().circumradius() + b.body().circumradius();
    const double tolerance = 1e-12 * size;
    const AxisTest fast = separatingAxisTest(a.body(), b.body(), warm, tolerance);
    const AxisTest full = separatingAxisTestReference(a.body(), b.body(), warm, tolerance);
    ++pairs;
    apart += fast.separated;
    on_edges += !fast.separated && fast.axis == AxisTest::Axis::kEdges;
    on_faces += !fast.separated && fast.axis != AxisTest::Axis::kEdges;
    if (a.body().shape->box() != nullptr && b.body().shape->box() != nullptr) {
      EXPECT_EQ(agreement(a.body(), b.body(), fast, full, size, boxes), "")
          << what << " pair " << pairs;
    } else {
      ++bitwise;
      EXPECT_EQ(differences(fast, full), "") << what << " pair " << pairs;
    }
  };
  const double scales[] = {1e-3, 1.0, 1e3};
  // Random pairs: random turns, from deep to apart, far from the origin at every scale.
  for (int i = 0; i < 6000; ++i) {
    const double sa = scales[i % 3], sb = scales[(i / 3) % 3] * (0.5 + unit(rng));
    const double shear = i % 4 == 1 ? 0.5 * unit(rng) : 0.0;  // every fourth B a parallelepiped
    const Placed b(boxShape(sb, sb * (0.3 + unit(rng)), sb, shear),
                   1e3 * sa * Vec3(unit(rng), unit(rng), 0), randomRotation(rng));
    const Placed probe(boxShape(sa, sa, sa * (0.3 + unit(rng))), Vec3::Zero(), Mat3::Identity());
    const double reach = probe.body().circumradius() + b.body().circumradius();
    const Vec3 at = b.body().position + 1.1 * reach * std::pow(unit(rng), 0.5) * randomUnit(rng);
    const Placed a(boxShape(sa, sa, sa), at, randomRotation(rng));
    const Vec3 warm = randomUnit(rng);
    check(a, b, i % 2 == 0 ? nullptr : &warm, "random");
    // Where the minimum is an edge axis, A moved out along it to graze B within round-off: the
    // edge axes that barely separate or barely overlap.
    const AxisTest first = separatingAxisTestReference(a.body(), b.body(), nullptr, 0.0);
    if (first.separated || first.axis != AxisTest::Axis::kEdges) continue;
    const double ulp = 1e-16 * (at.norm() + sa + sb);
    for (double hair : {-30.0, -3.0, -1.0, 0.0, 1.0, 3.0, 30.0}) {
      const Placed moved(boxShape(sa, sa, sa), at + (first.depth + hair * ulp) * first.normal,
                         a.body().rotation);
      check(moved, b, nullptr, "grazing edges");
    }
  }
  // A dense pack's neighbours: cubes aligned or turned by a hair, overlapping by 1e-3 to 1e-12 of
  // their size, touching or apart by as much, across a face, an edge or a corner.
  const Vec3 across[] = {Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(1, 1, 1), Vec3(0, 1, 0.3),
                         Vec3(1, 0.5, 0.2)};
  const double turns[] = {0.0, 1e-9, 1e-7, 1e-5, 1e-3};
  const double gaps[] = {-1e-3, -1e-9, -1e-12, 0.0, 1e-12, 1e-9, 1e-3};
  for (double scale : scales) {
    for (double size_ratio : {1.0, 0.5, 3.0}) {
      const auto cube_b = geometry::ConvexPolyhedron::fromPoints(shapes::cube(scale * size_ratio));
      const Vec3 origin = 37.0 * scale * Vec3(1, 2, 3);
      for (const Vec3& direction : across) {
        for (double angle : turns) {
          for (double gap : gaps) {
            const Placed b(cube_b, origin, Mat3::Identity());
            // A's centre so that along the unit components of `direction` the cubes overlap
            // by -gap (the half sizes add up to `reach`); the others shift A sideways.
            const double reach = 0.5 * scale * (1.0 + size_ratio) + gap * scale;
            const Vec3 offset = reach * direction;
            const Placed a(geometry::ConvexPolyhedron::fromPoints(shapes::cube(scale)),
                           origin + offset, turn(randomUnit(rng), angle));
            check(a, b, nullptr, "pack");
            const AxisTest first = separatingAxisTest(a.body(), b.body(), nullptr, 1e-12);
            check(a, b, &first.normal, "pack, warm");
          }
        }
      }
    }
  }
  std::printf(
      "box tests: %d pairs, %d apart, %d on a face axis, %d on an edge axis; %d with a "
      "parallelepiped, bit for bit; %d of two boxes: %d tied, %d apart by one test and within the "
      "tolerance of touching by the other, largest depth difference %.3f of the tolerance, "
      "largest angle %.3f of the allowed where not tied\n",
      pairs, apart, on_faces, on_edges, bitwise, boxes.compared, boxes.tied,
      boxes.apart_near_touching, boxes.worst_depth, boxes.worst_angle);
  EXPECT_GT(bitwise, 1000);
  EXPECT_GT(boxes.compared, 5000);
  EXPECT_GT(apart, 1000);
  EXPECT_GT(on_edges, 500);
  EXPECT_GT(on_faces, 1000);
}

// The box test tries the warm axis only where it ends apart or within 1e-6 of the pair's scale of
// touching (sat_obb.cpp). Its answer must be that of the warm axis tried first, bit for bit: the
// warm axis where it separates the boxes, else the answer without a warm axis; and a warm axis
// separates only pairs that the test finds apart or touching within far less than that margin.
// Random pairs, pairs moved apart along their normal to touching within a few ulp, and a dense
// pack's neighbours; warm axes at random, along the pair's normal and turned off it by a hair.
TEST(Sat, WarmAxisOnlyWhereNearlyApart) {
  std::mt19937_64 rng(17);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  int tried = 0, warm_decided = 0, overlapping = 0;
  double worst = 0.0;  // the largest depth (less the tolerance) of a pair a warm axis separated
  const auto check = [&](const Placed& a, const Placed& b, const Vec3& w) {
    const double size = a.body().circumradius() + b.body().circumradius();
    const double tolerance = 1e-12 * size;
    const AxisTest cold = separatingAxisTest(a.body(), b.body(), nullptr, tolerance);
    const AxisTest hot = separatingAxisTest(a.body(), b.body(), &w, tolerance);
    // The warm axis's test as the box test computes it.
    const auto centre = [](const Body& body) {
      return Vec3(body.position + body.rotation * body.shape->box()->centre);
    };
    const auto radius = [&](const Body& body) {
      const auto& half = body.shape->box()->half;
      const auto& faces = body.shape->axisFaces();
      return half[0] * std::abs(w.dot(body.faceNormal(faces[0]))) +
             half[1] * std::abs(w.dot(body.faceNormal(faces[1]))) +
             half[2] * std::abs(w.dot(body.faceNormal(faces[2])));
    };
    const bool separates =
        w.squaredNorm() > 0.0 &&
        (centre(a.body()) - centre(b.body())).dot(w) - radius(a.body()) - radius(b.body()) >= 0.0;
    ++tried;
    if (!separates) {
      EXPECT_EQ(differences(hot, cold), "") << "pair " << tried;
      return;
    }
    ++warm_decided;
    AxisTest along;
    along.separated = true;
    along.normal = w;
    EXPECT_EQ(differences(hot, along), "") << "pair " << tried;
    if (!cold.separated) {
      ++overlapping;
      worst = std::max(worst, (cold.depth - tolerance) / size);
    }
  };
  const auto warmAxes = [&](const Placed& a, const Placed& b) {
    const AxisTest cold = separatingAxisTest(a.body(), b.body(), nullptr, 0.0);
    check(a, b, randomUnit(rng));
    check(a, b, cold.normal);
    for (double hair : {1e-15, 1e-12, 1e-9, 1e-6}) {
      check(a, b, (cold.normal + hair * randomUnit(rng)).normalized());
    }
  };
  const double scales[] = {1e-3, 1.0, 1e3};
  for (int i = 0; i < 3000; ++i) {
    const double sa = scales[i % 3], sb = scales[(i / 3) % 3] * (0.5 + unit(rng));
    const Placed b(boxShape(sb, sb * (0.3 + unit(rng)), sb),
                   1e3 * sa * Vec3(unit(rng), unit(rng), 0), randomRotation(rng));
    const double reach = 0.9 * sa + b.body().circumradius();
    const Vec3 at = b.body().position + 1.1 * reach * std::pow(unit(rng), 0.5) * randomUnit(rng);
    const Placed a(boxShape(sa, sa, sa), at, randomRotation(rng));
    warmAxes(a, b);
    // A moved out along the normal to touch B within a few ulp of its coordinates.
    const AxisTest first = separatingAxisTestReference(a.body(), b.body(), nullptr, 0.0);
    if (first.separated) continue;
    const double ulp = 1e-16 * (at.norm() + sa + sb);
    for (double hair : {-30.0, -1.0, 0.0, 1.0, 30.0}) {
      const Placed moved(boxShape(sa, sa, sa), at + (first.depth + hair * ulp) * first.normal,
                         a.body().rotation);
      warmAxes(moved, b);
    }
  }
  // A dense pack's neighbours, aligned or turned by a hair, overlapping, touching or apart.
  const auto cube = geometry::ConvexPolyhedron::fromPoints(shapes::cube(1.0));
  for (const Vec3& direction : {Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(1, 1, 1), Vec3(1, 0.5, 0.2)}) {
    for (double angle : {0.0, 1e-9, 1e-5, 1e-3}) {
      for (double gap : {-1e-3, -1e-9, -1e-12, 0.0, 1e-12, 1e-9, 1e-3}) {
        const Vec3 origin(37.0, 74.0, 111.0);
        const Placed b(cube, origin, Mat3::Identity());
        const Placed a(cube, origin + (1.0 + gap) * direction, turn(randomUnit(rng), angle));
        warmAxes(a, b);
      }
    }
  }
  std::printf(
      "warm axes: %d tried, %d separated the pair, %d of them where the test without it found "
      "an overlap, at most %.3g of the size beyond the tolerance\n",
      tried, warm_decided, overlapping, worst);
  EXPECT_GT(warm_decided, 1000);
  EXPECT_GT(overlapping, 10);  // the grazing pairs reach the case the margin is for
  EXPECT_LT(worst, 1e-9);      // far inside the margin of 1e-6
}

// The bound of sat_box.cpp holds: on every edge axis of random pairs of boxes and parallelepipeds,
// the estimate lies within it of the overlap that the exact test computes (extent() along
// u.normalized()), and not by a wide margin (the screen is worth its cost only if the bound is near
// the round-off it covers).
TEST(Sat, BoxEdgeEstimatesAreWithinTheirBound) {
  std::mt19937_64 rng(16);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  double worst = 0.0;  // largest |estimate - overlap| / bound
  int axes = 0;
  for (int i = 0; i < 20000; ++i) {
    const double scale = std::pow(10.0, -3.0 + 6.0 * unit(rng));
    const double far = std::pow(10.0, 3.0 * unit(rng));  // distance from the origin, in sizes
    const Vec3 where = far * scale * randomUnit(rng);
    const double angle = i % 2 == 0 ? std::pow(10.0, -10.0 + 10.0 * unit(rng)) : 3.0;
    const double shear = i % 3 == 0 ? unit(rng) : 0.0;  // every third pair parallelepipeds
    const Placed b(boxShape(scale, scale * (0.2 + unit(rng)), scale, shear), where,
                   randomRotation(rng));
    const Placed a(boxShape(scale * (0.1 + 3 * unit(rng)), scale, scale, 0.5 * shear),
                   where + 2.0 * scale * unit(rng) * randomUnit(rng),
                   turn(randomUnit(rng), angle) * b.body().rotation);
    const sat_detail::Cloud ca(a.body()), cb(b.body());
    sat_detail::EdgeEstimates estimates;
    ASSERT_TRUE(sat_detail::estimateBoxEdges(a.body(), b.body(), ca, cb, estimates));
    for (int axis = 0; axis < 9; ++axis) {
      if (!(estimates.exists & (1u << axis))) continue;
      const Vec3 u = ca.e[estimates.k[axis / 3]].cross(cb.e[estimates.l[axis % 3]]).normalized();
      const auto ea = sat_detail::extent(ca, u), eb = sat_detail::extent(cb, u);
      const double overlap = std::min(eb.hi - ea.lo, ea.hi - eb.lo);
      const double error = std::abs(estimates.overlap[axis] - overlap);
      ASSERT_LE(error, estimates.bound[axis]) << "pair " << i << " axis " << axis;
      worst = std::max(worst, error / estimates.bound[axis]);
      ++axes;
    }
  }
  std::printf("box edge estimates: %d axes, largest error %.3f of the bound\n", axes, worst);
  EXPECT_GT(axes, 100000);
  EXPECT_GT(worst, 1e-3);  // the bound is not loose by orders of magnitude
}

// Which shapes take the classical box test: rectangular boxes in any frame (a rotation by
// transformed() keeps them boxes within round-off), not sheared boxes, prisms or tetrahedra; the
// frame's corners sit at their sign patterns and its axis edges along its axes.
TEST(Sat, BoxFrameOfShapes) {
  std::mt19937_64 rng(7);
  const auto box = boxShape(2.0, 1.0, 0.5);
  const auto turned = box.transformed(randomRotation(rng), Vec3(3, -1, 2));
  for (const auto* shape : {&box, &turned}) {
    const geometry::BoxFrame* frame = shape->box();
    ASSERT_NE(frame, nullptr);
    EXPECT_LE(frame->skew, geometry::BoxFrame::kMaxSkew);
    for (int c = 0; c < 8; ++c) {
      Vec3 corner = frame->centre;
      for (int k = 0; k < 3; ++k) {
        corner += ((c >> k & 1) ? 1.0 : -1.0) * frame->half[k] * frame->axis[k];
      }
      EXPECT_LT((corner - shape->vertices()[frame->corner[c]]).norm(), 1e-14 * 2.0) << c;
    }
    for (int i = 0; i < 3; ++i) {
      const auto& edge = shape->edges()[shape->axisEdges()[i]];
      const Vec3 e = shape->vertices()[edge.v1] - shape->vertices()[edge.v0];
      EXPECT_NEAR(e.dot(frame->axis[frame->edge_axis[i]]) * frame->edge_sign[i],
                  2.0 * frame->half[frame->edge_axis[i]], 1e-14);
    }
    // The face table: +a_k is the axis face itself, every face once, along its own axis and sign.
    std::vector<int> seen(6, 0);
    for (int k = 0; k < 3; ++k) {
      EXPECT_EQ(frame->face[2 * k], shape->axisFaces()[k]);
      for (int side = 0; side < 2; ++side) {
        const int f = frame->face[2 * k + side];
        ASSERT_TRUE(f >= 0 && f < 6);
        ++seen[f];
        EXPECT_NEAR(shape->faces()[f].normal.dot(frame->axis[k]), side == 0 ? 1.0 : -1.0, 1e-14);
      }
    }
    EXPECT_EQ(seen, std::vector<int>(6, 1));
  }
  EXPECT_EQ(boxShape(1.0, 1.0, 1.0, 0.3).box(), nullptr);
  EXPECT_EQ(smallShape(1, 1.0).box(), nullptr);  // a tetrahedron
  EXPECT_EQ(smallShape(2, 1.0).box(), nullptr);  // a triangular prism
  EXPECT_NE(smallShape(3, 1.0).box(), nullptr);  // a flat box
}

// KernelParams::separating_axes = false: both kernels give GJK + EPA's answer, bit for bit.
TEST(Sat, SwitchedOffKeepsGjkEpa) {
  std::mt19937_64 rng(5);
  const auto cube = geometry::ConvexPolyhedron::fromPoints(shapes::cube(1.0));
  const Placed a(cube, Vec3(0.9, 0.2, 0.1), randomRotation(rng));
  const Placed b(cube, Vec3::Zero(), randomRotation(rng));
  KernelParams params;
  params.separating_axes = false;
  for (const char* name : {"gjk-epa", "gjk-epa-ipm"}) {
    particles::PairState s1, s2;
    const Contact off = makeKernel(name, params)->collideForSubContacts(a.body(), b.body(), &s1);
    const Contact epa = gjkEpaContact(a.body(), b.body(), &s2);
    ASSERT_TRUE(epa.touching);
    EXPECT_EQ(off.normal, epa.normal) << name;
    EXPECT_EQ(off.depth, epa.depth) << name;
    EXPECT_EQ(off.point, epa.point) << name;
    EXPECT_EQ(s1.warm_direction, s2.warm_direction) << name;
  }
}

}  // namespace
}  // namespace polydem::contact
