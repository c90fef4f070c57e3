// ConvexPolyhedron::fromPoints: polygon faces, dropped points, errors, near-degenerate input and
// scale invariance.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <string>

#include "polydem/core/error.h"
#include "polydem/geometry/convex_polyhedron.h"
#include "polydem/geometry/shapes.h"
#include "polyhedron_checks.h"

namespace polydem::geometry {
namespace {

using testing::expectValidPolyhedron;

std::vector<int> faceSizes(const ConvexPolyhedron& p) {
  std::vector<int> sizes;
  for (const Face& f : p.faces()) sizes.push_back(static_cast<int>(f.vertices.size()));
  std::sort(sizes.begin(), sizes.end());
  return sizes;
}

/// The message of the GeometryError that building from `points` throws ("" if none).
std::string buildError(const std::vector<Vec3>& points) {
  try {
    ConvexPolyhedron::fromPoints(points);
  } catch (const GeometryError& e) {
    return e.what();
  }
  return "";
}

TEST(HullBuilding, CubeHasSixQuadsTwelveEdgesEightVertices) {
  const auto points = shapes::cube(2.0);
  BuildReport report;
  const auto cube = ConvexPolyhedron::fromPoints(points, &report);
  EXPECT_EQ(cube.vertices().size(), 8u);
  EXPECT_EQ(cube.edges().size(), 12u);
  EXPECT_EQ(faceSizes(cube), std::vector<int>(6, 4));
  // Vertices keep the input order and coordinates exactly.
  for (int i = 0; i < 8; ++i) {
    EXPECT_EQ(cube.vertices()[i], points[i]);
    EXPECT_EQ(report.vertex_of_input[i], i);
  }
  EXPECT_TRUE(report.interior_points.empty());
  EXPECT_TRUE(report.boundary_points.empty());
  // Axis-aligned faces have exact axis normals.
  for (const Face& f : cube.faces()) {
    EXPECT_EQ(f.normal.cwiseAbs().maxCoeff(), 1.0);
    EXPECT_EQ(f.area, 4.0);
    EXPECT_EQ(f.offset, 1.0);
  }
  expectValidPolyhedron(cube);
}

TEST(HullBuilding, PlatonicSolidsAndPrismsHaveTheirPolygonFaces) {
  const auto oct = ConvexPolyhedron::fromPoints(shapes::octahedron(1.0));
  EXPECT_EQ(faceSizes(oct), std::vector<int>(8, 3));
  EXPECT_EQ(oct.edges().size(), 12u);
  const auto tet = ConvexPolyhedron::fromPoints(shapes::tetrahedron(1.0));
  EXPECT_EQ(faceSizes(tet), std::vector<int>(4, 3));
  const auto ico = ConvexPolyhedron::fromPoints(shapes::icosahedron(1.0));
  EXPECT_EQ(faceSizes(ico), std::vector<int>(20, 3));
  EXPECT_EQ(ico.edges().size(), 30u);
  const auto dod = ConvexPolyhedron::fromPoints(shapes::dodecahedron(1.0));
  EXPECT_EQ(faceSizes(dod), std::vector<int>(12, 5));
  EXPECT_EQ(dod.edges().size(), 30u);
  const auto hex = ConvexPolyhedron::fromPoints(shapes::hexagonalPrism(0.3, 2.0));
  EXPECT_EQ(faceSizes(hex), (std::vector<int>{4, 4, 4, 4, 4, 4, 6, 6}));
  const auto ridge =
      ConvexPolyhedron::fromPoints(shapes::ridgePrism(Vec3(-1, 0, 0), Vec3(1, 0, 0), 0.5, 1.0));
  EXPECT_EQ(faceSizes(ridge), (std::vector<int>{3, 3, 4, 4, 4}));
  const auto pyramid = ConvexPolyhedron::fromPoints(
      shapes::squarePyramid(Vec3::Zero(), 1.0, 1.0, shapes::Apex::kUp, degToRad(45.0)));
  EXPECT_EQ(faceSizes(pyramid), (std::vector<int>{3, 3, 3, 3, 4}));
  for (const auto* p : {&oct, &tet, &ico, &dod, &hex, &ridge, &pyramid}) expectValidPolyhedron(*p);
}

TEST(HullBuilding, GridPointsOnEdgesAndFacesAreBoundaryTheCentreInterior) {
  // The 3x3x3 grid: 8 corners, 12 edge midpoints + 6 face centres on the boundary, 1 interior.
  std::vector<Vec3> points;
  for (int i = 0; i < 27; ++i) points.emplace_back(i % 3, (i / 3) % 3, i / 9);
  BuildReport report;
  const auto p = ConvexPolyhedron::fromPoints(points, &report);
  EXPECT_EQ(faceSizes(p), std::vector<int>(6, 4));
  EXPECT_EQ(report.vertex_of_input, (std::vector<int>{0, 2, 6, 8, 18, 20, 24, 26}));
  EXPECT_EQ(report.interior_points, std::vector<int>{13});
  EXPECT_EQ(report.boundary_points.size(), 18u);
  for (int i = 0; i < 8; ++i) EXPECT_EQ(p.vertices()[i], points[report.vertex_of_input[i]]);
  expectValidPolyhedron(p);
}

TEST(HullBuilding, ErrorsNameWhatIsWrong) {
  EXPECT_NE(
      buildError({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)}).find("at least 4 points, got 3"),
      std::string::npos);

  const std::string flat =
      buildError({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(1, 1, 0), Vec3(0.5, 0.2, 0)});
  EXPECT_NE(flat.find("flat"), std::string::npos) << flat;
  EXPECT_NE(flat.find("0, 1, 2, 3, 4"), std::string::npos) << flat;

  auto cube = shapes::cube(1.0);
  cube.push_back(cube[5] + Vec3(1e-13, 0, 0));
  const std::string dup = buildError(cube);
  EXPECT_NE(dup.find("duplicate"), std::string::npos) << dup;
  EXPECT_NE(dup.find("points 5 and 8"), std::string::npos) << dup;

  auto with_nan = shapes::cube(1.0);
  with_nan[3].y() = std::numeric_limits<double>::quiet_NaN();
  const std::string nan = buildError(with_nan);
  EXPECT_NE(nan.find("point(s) 3 "), std::string::npos) << nan;
  EXPECT_NE(nan.find("NaN or infinite"), std::string::npos) << nan;

  auto with_inf = shapes::cube(1.0);
  with_inf[6].z() = std::numeric_limits<double>::infinity();
  EXPECT_NE(buildError(with_inf).find("point(s) 6 "), std::string::npos);

  // Collinear points are flat as well.
  EXPECT_NE(buildError({Vec3(0, 0, 0), Vec3(1, 1, 1), Vec3(2, 2, 2), Vec3(3, 3, 3)}).find("flat"),
            std::string::npos);
}

TEST(HullBuilding, ThinnerThanTheToleranceIsFlatThickerIsASliver) {
  const double size = 1.0;
  for (double height : {1e-11, 5e-11}) {
    const std::vector<Vec3> almost_flat{Vec3(0, 0, 0), Vec3(size, 0, 0), Vec3(0, size, 0),
                                        Vec3(0.3, 0.3, height)};
    EXPECT_NE(buildError(almost_flat).find("flat"), std::string::npos) << height;
  }
  for (double height : {1e-8, 1e-6}) {
    const std::vector<Vec3> sliver{Vec3(0, 0, 0), Vec3(size, 0, 0), Vec3(0, size, 0),
                                   Vec3(0.3, 0.3, height)};
    const auto p = ConvexPolyhedron::fromPoints(sliver);
    EXPECT_EQ(faceSizes(p), std::vector<int>(4, 3));
    EXPECT_NEAR(p.volume(), height / 6.0, 1e-12 * height);
    double surface = 0.0;
    for (const Face& f : p.faces()) surface += f.area;
    EXPECT_NEAR(p.inradius(), 3.0 * p.volume() / surface, 1e-12 * p.inradius());  // tetrahedron
    expectValidPolyhedron(p);
  }
}

TEST(HullBuilding, NearlyCoplanarPointsAreMergedIntoTheFace) {
  // A point 1e-12 (relative) above the centre of the top face: still a cube, point on the boundary.
  auto points = shapes::cube(1.0);
  points.push_back(Vec3(0.1, -0.2, 0.5 + 1e-12));
  BuildReport report;
  const auto p = ConvexPolyhedron::fromPoints(points, &report);
  EXPECT_EQ(faceSizes(p), std::vector<int>(6, 4));
  EXPECT_EQ(report.boundary_points, std::vector<int>{8});
  expectValidPolyhedron(p);

  // 1e-6 above is a real apex: four triangles replace the top quad.
  points.back().z() = 0.5 + 1e-6;
  const auto tent = ConvexPolyhedron::fromPoints(points, &report);
  EXPECT_EQ(faceSizes(tent), (std::vector<int>{3, 3, 3, 3, 4, 4, 4, 4, 4}));
  EXPECT_TRUE(report.boundary_points.empty());
  expectValidPolyhedron(tent);
}

TEST(HullBuilding, JitteredPointsOnCubeFacesStillGiveSixQuads) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-0.5, 0.5), jitter(-1e-12, 1e-12);
  auto points = shapes::cube(1.0);
  for (int i = 0; i < 600; ++i) {
    Vec3 p(u(rng), u(rng), u(rng));
    const int axis = i % 3;
    p[axis] = ((i / 3) % 2 ? 0.5 : -0.5) + jitter(rng);
    points.push_back(p);
  }
  // Corners jittered too, so no face is exactly planar.
  for (int i = 0; i < 8; ++i) points[i] += Vec3(jitter(rng), jitter(rng), jitter(rng));
  BuildReport report;
  const auto p = ConvexPolyhedron::fromPoints(points, &report);
  EXPECT_EQ(faceSizes(p), std::vector<int>(6, 4));
  EXPECT_EQ(report.vertex_of_input, (std::vector<int>{0, 1, 2, 3, 4, 5, 6, 7}));
  EXPECT_EQ(report.boundary_points.size() + report.interior_points.size(), 600u);
  EXPECT_NEAR(p.volume(), 1.0, 1e-10);
  expectValidPolyhedron(p);
}

TEST(HullBuilding, CornerCutByLessThanTheToleranceStaysACorner) {
  // Corner 0 of the unit cube, (0.5, 0.5, 0.5), replaced by three points on its edges. Cut by less
  // than the plane tolerance (1e-10 of the size 1.73), the cube keeps 8 corners and 6 quads; cut
  // by 1e-6, it gains a triangle.
  for (double cut : {1.5e-10, 1e-6}) {
    auto points = shapes::cube(1.0);
    const Vec3 corner = points[0];
    points.erase(points.begin());
    for (int k = 0; k < 3; ++k) points.push_back(corner - cut * Vec3::Unit(k));
    BuildReport report;
    const auto p = ConvexPolyhedron::fromPoints(points, &report);
    if (cut < 1e-9) {
      EXPECT_EQ(p.vertices().size(), 8u);
      EXPECT_EQ(faceSizes(p), std::vector<int>(6, 4));
      EXPECT_EQ(report.boundary_points.size(), 2u);
    } else {
      EXPECT_EQ(p.vertices().size(), 10u);
      EXPECT_EQ(faceSizes(p), (std::vector<int>{3, 4, 4, 4, 5, 5, 5}));
    }
    expectValidPolyhedron(p);
  }
}

TEST(HullBuilding, RandomHullsAreValidPolyhedra) {
  for (int n : {4, 5, 10, 50, 300}) {
    for (std::uint64_t seed = 1; seed <= 4; ++seed) {
      const auto points = shapes::randomConvex(n, seed, Vec3(1.0, 0.6, 0.3), 0.3);
      const auto p = ConvexPolyhedron::fromPoints(points);
      EXPECT_EQ(p.vertices().size(), static_cast<std::size_t>(n)) << n << " " << seed;
      expectValidPolyhedron(p);
    }
  }
  // Points filling a box: most are interior; every input point is accounted for once.
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<Vec3> cloud;
  for (int i = 0; i < 400; ++i) cloud.emplace_back(u(rng), 0.5 * u(rng), 2.0 * u(rng));
  BuildReport report;
  const auto p = ConvexPolyhedron::fromPoints(cloud, &report);
  EXPECT_EQ(
      report.vertex_of_input.size() + report.interior_points.size() + report.boundary_points.size(),
      cloud.size());
  EXPECT_TRUE(std::is_sorted(report.vertex_of_input.begin(), report.vertex_of_input.end()));
  for (int i : report.interior_points) EXPECT_TRUE(p.contains(cloud[i]));
  expectValidPolyhedron(p);
}

TEST(HullBuilding, SameTopologyAtMillimetreAndKilometreScale) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> jitter(-1e-12, 1e-12);
  auto jittered = shapes::cube(1.0);
  for (int i = 0; i < 40; ++i) {
    Vec3 p(0.4 * jitter(rng) * 1e12, 0.3, 0.5 + jitter(rng));
    jittered.push_back(p);
  }
  for (const auto& points : {shapes::cube(1.0), shapes::randomConvex(60, 5), jittered,
                             shapes::hexagonalPrism(0.2, 1.0)}) {
    const auto ref = ConvexPolyhedron::fromPoints(points);
    for (double scale : {1e-3, 1e3}) {
      std::vector<Vec3> scaled;
      for (const Vec3& x : points) scaled.push_back(scale * x + Vec3(0.3, -2.0, 7.0) * scale);
      BuildReport report;
      const auto p = ConvexPolyhedron::fromPoints(scaled, &report);
      ASSERT_EQ(p.faces().size(), ref.faces().size());
      for (std::size_t f = 0; f < ref.faces().size(); ++f) {
        EXPECT_EQ(p.faces()[f].vertices, ref.faces()[f].vertices);
      }
      EXPECT_NEAR(p.volume(), ref.volume() * std::pow(scale, 3), 1e-12 * p.volume());
      EXPECT_LT((p.inertia() - ref.inertia() * std::pow(scale, 5)).norm(),
                1e-12 * p.inertia().norm());
      EXPECT_LT((p.centroid() - scale * (ref.centroid() + Vec3(0.3, -2.0, 7.0))).norm(),
                1e-12 * p.lengthScale());
    }
  }
}

TEST(HullBuilding, DeterministicToTheBit) {
  const auto points = shapes::randomConvex(200, 9);
  const auto a = ConvexPolyhedron::fromPoints(points);
  const auto b = ConvexPolyhedron::fromPoints(points);
  ASSERT_EQ(a.faces().size(), b.faces().size());
  for (std::size_t f = 0; f < a.faces().size(); ++f) {
    EXPECT_EQ(a.faces()[f].vertices, b.faces()[f].vertices);
    EXPECT_EQ(a.faces()[f].normal, b.faces()[f].normal);
  }
  EXPECT_EQ(a.volume(), b.volume());
  EXPECT_EQ(a.inertia(), b.inertia());
  // Faces in canonical order: each starts at its lowest vertex, the lists sorted.
  for (std::size_t f = 0; f < a.faces().size(); ++f) {
    const auto& v = a.faces()[f].vertices;
    EXPECT_EQ(*std::min_element(v.begin(), v.end()), v.front());
    if (f > 0) {
      EXPECT_LT(a.faces()[f - 1].vertices, v);
    }
  }
}

}  // namespace
}  // namespace polydem::geometry
