// The Intersection Polygon Method (contact/point/ipm.h, Keissar section 2.3) against an independent
// computation: the polygon where a plane cuts A and B is the set of plane points satisfying every
// face inequality of both; here its corners are enumerated by brute force (every pair of face
// traces intersected, the points inside all kept) and ordered by angle.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>

#include "contact_test_util.h"
#include "polydem/contact/gjk/gjk_epa.h"
#include "polydem/contact/point/ipm.h"
#include "polydem/geometry/plane_section.h"
#include "polydem/geometry/shapes.h"

namespace polydem::contact {
namespace {

using testing::Placed;
using testing::placeWorld;
using testing::randomRotation;
using testing::randomUnit;

struct Line {  // g . y <= h
  Vec2 g;
  double h;
};

struct Patch {
  double area = 0.0;
  Vec2 centroid = Vec2::Zero();
};

/// Brute-force vertex enumeration of {y : g_i . y <= h_i for all i}, a bounded convex polygon.
Patch enumerate(const std::vector<Line>& lines, double tolerance) {
  std::vector<Vec2> corners;
  for (std::size_t i = 0; i < lines.size(); ++i) {
    for (std::size_t j = i + 1; j < lines.size(); ++j) {
      const double det = lines[i].g.x() * lines[j].g.y() - lines[i].g.y() * lines[j].g.x();
      if (std::abs(det) < 1e-12 * lines[i].g.norm() * lines[j].g.norm()) continue;
      const Vec2 y((lines[i].h * lines[j].g.y() - lines[j].h * lines[i].g.y()) / det,
                   (lines[i].g.x() * lines[j].h - lines[j].g.x() * lines[i].h) / det);
      bool inside = true;
      for (const Line& l : lines) inside = inside && l.g.dot(y) - l.h <= tolerance * l.g.norm();
      if (inside) corners.push_back(y);
    }
  }
  Patch p;
  if (corners.size() < 3) return p;
  Vec2 mean = Vec2::Zero();
  for (const Vec2& c : corners) mean += c;
  mean /= static_cast<double>(corners.size());
  std::sort(corners.begin(), corners.end(), [&](const Vec2& a, const Vec2& b) {
    return std::atan2(a.y() - mean.y(), a.x() - mean.x()) <
           std::atan2(b.y() - mean.y(), b.x() - mean.x());
  });
  Vec2 moment = Vec2::Zero();
  for (std::size_t k = 0; k < corners.size(); ++k) {  // shoelace about the mean
    const Vec2 a = corners[k] - mean, b = corners[(k + 1) % corners.size()] - mean;
    const double c = a.x() * b.y() - a.y() * b.x();
    p.area += 0.5 * c;
    moment += c * (a + b) / 3.0;
  }
  p.centroid = mean + moment / (2.0 * p.area);
  return p;
}

/// The plane's own frame, built here independently of geometry::PlaneFrame.
struct Frame {
  Vec3 origin, n, u, v;
  Frame(const Vec3& normal, const Vec3& point) : origin(point), n(normal) {
    u = (std::abs(n.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY()).cross(n).normalized();
    v = n.cross(u);
  }
};

/// Traces on the plane of every face of a placed body, from its world vertices.
void addTraces(const Body& body, const Frame& f, std::vector<Line>& lines) {
  for (const auto& face : body.shape->faces()) {
    const Vec3& p0 = body.vertices[face.vertices[0]];
    const Vec3 n = (body.vertices[face.vertices[1]] - p0)
                       .cross(body.vertices[face.vertices[2]] - p0)
                       .normalized();
    lines.push_back({Vec2(n.dot(f.u), n.dot(f.v)), n.dot(p0 - f.origin)});
  }
}

Patch exactPatch(const Body& a, const Body& b, const Frame& f) {
  std::vector<Line> lines;
  addTraces(a, f, lines);
  addTraces(b, f, lines);
  // Faces parallel to the plane are constraints 0 <= h: drop them when met (the plane crosses
  // both bodies in every case used here).
  std::erase_if(lines, [](const Line& l) { return l.g.norm() < 1e-12; });
  return enumerate(lines, 1e-12);
}

TEST(Ipm, FaceFaceWithYawAndOffsetsGivesTheOverlapPatchCentroid) {
  // A unit cube turned by a yaw about z, partly hanging off a box below it, penetrating it by
  // 1e-5 .. 1e-3: the patch is the rotated square clipped by the box's top rectangle. Every
  // other pair is moved by a random rigid motion and scaled by 1e-3, 1 or 1e3 as a whole.
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const geometry::ConvexPolyhedron cube =
      geometry::ConvexPolyhedron::fromPoints(geometry::shapes::cube(1.0));
  double worst = 0.0;
  int partial = 0;
  for (int i = 0; i < 300; ++i) {
    const double yaw = 2.0 * kPi * unit(rng);
    const double depth = std::pow(10.0, -5.0 + 2.0 * unit(rng));
    const Vec3 centre(1.2 * (unit(rng) - 0.5), 1.2 * (unit(rng) - 0.5), 0.5 - depth);
    const Mat3 R = Eigen::AngleAxisd(yaw, Vec3::UnitZ()).toRotationMatrix();
    const Vec3 lo(-0.3 - unit(rng), -0.3 - unit(rng), -1.0),
        hi(0.3 + unit(rng), 0.3 + unit(rng), 0);
    const bool moved = i % 2 == 1;
    const Mat3 G = moved ? randomRotation(rng) : Mat3::Identity();
    const double scale = moved ? std::pow(10.0, 3.0 * (i % 3) - 3.0) : 1.0;
    const Vec3 t = moved ? Vec3(scale * 4.0 * randomUnit(rng)) : Vec3::Zero();
    const Placed a(cube.scaled(scale), t + scale * (G * centre), G * R);
    const Placed b(
        geometry::ConvexPolyhedron::fromPoints(geometry::shapes::box(lo, hi)).scaled(scale), t, G);

    // Independent answer in the horizontal plane z = -depth / 2: square footprint and rectangle.
    std::vector<Line> lines;
    for (int k = 0; k < 4; ++k) {
      const Vec2 g(std::cos(yaw + k * kPi / 2), std::sin(yaw + k * kPi / 2));
      lines.push_back({g, g.dot(centre.head<2>()) + 0.5});
    }
    lines.push_back({Vec2(1, 0), hi.x()});
    lines.push_back({Vec2(-1, 0), -lo.x()});
    lines.push_back({Vec2(0, 1), hi.y()});
    lines.push_back({Vec2(0, -1), -lo.y()});
    const Patch exact = enumerate(lines, 1e-12);
    partial += exact.area < 1.0 - 1e-9;
    const Vec3 expected =
        t + scale * (G * Vec3(exact.centroid.x(), exact.centroid.y(), -0.5 * depth));

    const Contact r = GjkEpaIpmKernel().collide(a.body(), b.body(), nullptr);
    ASSERT_TRUE(r.touching);
    EXPECT_EQ(r.status, Status::kOk);
    EXPECT_LT(angleBetween(r.normal, G * Vec3::UnitZ()), 1e-12);
    EXPECT_NEAR(r.depth, scale * depth, 1e-12 * scale);
    const double error = (r.point - expected).norm() / scale;
    EXPECT_LT(error, 1e-10) << "pose " << i;
    worst = std::max(worst, error);
  }
  std::printf(
      "face-face with yaw: worst point error %.2e of the size over 300 poses (%d partly "
      "off B)\n",
      worst, partial);
  EXPECT_GT(partial, 50);
}

TEST(Ipm, TiltedPlanesThroughRandomPolyhedraMatchVertexEnumeration) {
  std::mt19937_64 rng(9);
  std::uniform_int_distribution<int> count(8, 40);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  int compared = 0;
  for (int i = 0; i < 300; ++i) {
    auto shape_a = geometry::ConvexPolyhedron::fromPoints(
        geometry::shapes::randomConvex(count(rng), rng(), Vec3(1.0, 0.8, 0.6), 0.2));
    auto shape_b = geometry::ConvexPolyhedron::fromPoints(
        geometry::shapes::randomConvex(count(rng), rng(), Vec3(0.7, 1.1, 0.9), 0.2));
    const Vec3 where(3.0, -2.0, 1.0);
    const Placed a(std::move(shape_a), where + 0.6 * randomUnit(rng), randomRotation(rng));
    const Placed b(std::move(shape_b), where, randomRotation(rng));
    const Vec3 n = randomUnit(rng);
    const Vec3 point = 0.5 * (a.body().position + b.body().position);
    const auto ipm = intersectionPolygon(a.body(), b.body(), n, point);
    const Frame f(n, point);
    const Patch exact = exactPatch(a.body(), b.body(), f);
    if (exact.area < 1e-6) {
      EXPECT_FALSE(ipm.has_value() && ipm->area > 1e-6) << "pair " << i;
      continue;
    }
    ++compared;
    ASSERT_TRUE(ipm.has_value()) << "pair " << i;
    EXPECT_NEAR(ipm->area, exact.area, 1e-12) << "pair " << i;
    const Vec3 expected = f.origin + exact.centroid.x() * f.u + exact.centroid.y() * f.v;
    EXPECT_LT((ipm->centroid - expected).norm(), 1e-12) << "pair " << i;
    EXPECT_NEAR(n.dot(ipm->centroid - point), 0.0, 1e-14);  // on the plane
  }
  EXPECT_GT(compared, 150);
}

TEST(Ipm, PlaneThroughVerticesOfOctahedra) {
  // The plane z = 0 holds four vertices of each octahedron and crosses no edge strictly: the
  // sections are the squares |x| + |y| <= 1 and |x - 0.5| + |y| <= 1, each corner once.
  const auto a = placeWorld(geometry::shapes::octahedron(std::sqrt(2.0)));
  std::vector<Vec3> moved = geometry::shapes::octahedron(std::sqrt(2.0));
  for (auto& v : moved) v += Vec3(0.5, 0, 0);
  const auto b = placeWorld(moved);
  const auto frame = geometry::PlaneFrame::make(Vec3::UnitZ(), Vec3(0.2, 0.1, 0));
  std::vector<double> heights;
  std::vector<Vec2> polygon, points;
  geometry::planeHeights(a->body().vertices, frame, heights);
  geometry::sectionPolygon(a->shape(), a->body().vertices, frame, heights, polygon, points);
  ASSERT_EQ(polygon.size(), 4u);
  EXPECT_NEAR(geometry::areaCentroid(polygon).area, 2.0, 1e-15);
  std::vector<geometry::HalfPlane> planes;
  EXPECT_TRUE(geometry::sectionHalfPlanes(a->shape(), a->body().vertices, Mat3::Identity(), frame,
                                          heights, planes));
  EXPECT_EQ(planes.size(), 4u);  // the four lower faces, once each
  const auto m = intersectionPolygon(a->body(), b->body(), Vec3::UnitZ(), Vec3(0.2, 0.1, 0));
  ASSERT_TRUE(m.has_value());
  const Patch exact = exactPatch(a->body(), b->body(), Frame(Vec3::UnitZ(), Vec3(0.2, 0.1, 0)));
  EXPECT_NEAR(m->area, exact.area, 1e-15);
  // By hand: the quadrilateral (-0.5, 0), (0.25, -0.75), (1, 0), (0.25, 0.75): area 1.5 * 0.75.
  EXPECT_NEAR(m->area, 1.125, 1e-15);
  EXPECT_NEAR((m->centroid - Vec3(0.25, 0, 0)).norm(), 0.0, 1e-15);
}

TEST(Ipm, MidOverlapPointIsHalfWayBetweenTheSurfaces) {
  const auto a = placeWorld(geometry::shapes::box({0, 0, -0.25}, {1, 1, 1}));
  const auto b = placeWorld(geometry::shapes::box({-1, -1, -1}, {2, 2, 0}));
  const Vec3 p = midOverlapPoint(a->body(), b->body(), Vec3::UnitZ(), Vec3(5, 6, 7));
  EXPECT_NEAR((p - Vec3(5, 6, -0.125)).norm(), 0.0, 1e-15);
}

TEST(Ipm, TouchingSectionsOrAMissedBodyGiveNothing) {
  // Side by side, sharing the face x = 1: the sections share an edge, no area.
  const auto a = placeWorld(geometry::shapes::box({0, 0, 0}, {1, 1, 1}));
  const auto b = placeWorld(geometry::shapes::box({1, 0, 0}, {2, 1, 1}));
  EXPECT_FALSE(intersectionPolygon(a->body(), b->body(), Vec3::UnitZ(), Vec3(1, 0.5, 0.5)));
  // Corner to corner.
  const auto c = placeWorld(geometry::shapes::box({1, 1, 0}, {2, 2, 1}));
  EXPECT_FALSE(intersectionPolygon(a->body(), c->body(), Vec3::UnitZ(), Vec3(1, 1, 0.5)));
  // The plane z = 1.5 misses both; z = 0.5 with B moved up misses B.
  EXPECT_FALSE(intersectionPolygon(a->body(), b->body(), Vec3::UnitZ(), Vec3(0, 0, 1.5)));
  const auto d = placeWorld(geometry::shapes::box({0, 0, 2}, {1, 1, 3}));
  EXPECT_FALSE(intersectionPolygon(a->body(), d->body(), Vec3::UnitZ(), Vec3(0, 0, 0.5)));
  // Overlapping: the shared square.
  const auto e = placeWorld(geometry::shapes::box({0.5, 0.5, 0}, {2, 2, 1}));
  const auto m = intersectionPolygon(a->body(), e->body(), Vec3::UnitZ(), Vec3(0, 0, 0.5));
  ASSERT_TRUE(m.has_value());
  EXPECT_NEAR(m->area, 0.25, 1e-15);
  EXPECT_NEAR((m->centroid - Vec3(0.75, 0.75, 0.5)).norm(), 0.0, 1e-15);
}

TEST(Ipm, KernelFallsBackToEpaWhereThePlaneMissesTheOverlap) {
  // A small cube deep inside a large one: EPA pushes it out through z = 2, and the plane half way
  // between its bottom (z = 0.3) and B's top (z = 2) passes above it: no polygon, EPA's point.
  const auto a = placeWorld(geometry::shapes::box({0.1, 0.2, 0.3}, {0.3, 0.4, 0.5}));
  const auto b = placeWorld(geometry::shapes::box({-2, -2, -2}, {2, 2, 2}));
  // With GJK + EPA for every pair: EPA's point.
  const Contact epa = GjkEpaKernel().collide(a->body(), b->body(), nullptr);
  const Contact ipm = GjkEpaIpmKernel(false).collide(a->body(), b->body(), nullptr);
  ASSERT_TRUE(ipm.touching);
  EXPECT_EQ(ipm.status, Status::kDegenerate);
  EXPECT_EQ(ipm.point, epa.point);
  EXPECT_EQ(ipm.depth, epa.depth);
  // With the separating-axis test (contact/sat/sat.h): the exact normal and depth, and its point on
  // the plane half way through the overlap (z = 1.15). Its lateral position is that of the
  // vertex-face contact the winning axis stands for: A's top face ties with B's, A's axes come
  // first, so B's first highest vertex (-2, -2, 2) is taken, outside A; EPA's point was inside.
  // A known weakness of the fallback on face-face ties (docs/kernels/gjk-epa.md), recorded here.
  const Contact sat = GjkEpaIpmKernel().collide(a->body(), b->body(), nullptr);
  ASSERT_TRUE(sat.touching);
  EXPECT_EQ(sat.status, Status::kDegenerate);
  EXPECT_EQ(sat.normal, Vec3::UnitZ());
  EXPECT_NEAR(sat.depth, 1.7, 1e-15);
  EXPECT_NEAR(epa.depth, 1.7, 1e-12 * 2 * (a->body().circumradius() + b->body().circumradius()));
  EXPECT_NEAR(sat.point.z(), 1.15, 1e-15);
  std::printf("separating-axis fallback point (%g, %g, %g), EPA's (%g, %g, %g)\n", sat.point.x(),
              sat.point.y(), sat.point.z(), epa.point.x(), epa.point.y(), epa.point.z());
}

}  // namespace
}  // namespace polydem::contact
