// The nearest-face partition (face_regions.h): the neighbours listed for a face's region are
// enough to tell whether a point lies in it, on regular, irregular and random polyhedra, at any
// scale and pose; copies share the partition.
#include "polydem/geometry/face_regions.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "polydem/geometry/convex_polyhedron.h"
#include "polydem/geometry/shapes.h"

namespace polydem::geometry {
namespace {

// Inward distance from x to the plane of face k.
double depth(const ConvexPolyhedron& p, int k, const Vec3& x) {
  return p.faces()[k].offset - p.faces()[k].normal.dot(x);
}

bool lists(const FaceRegions& r, int k, int l) {
  const auto n = r.of(k);
  return std::find(n.begin(), n.end(), l) != n.end();
}

// Points inside p: uniform in its bounding ball, and crowded about the in-centre, where most
// regions meet.
std::vector<Vec3> insidePoints(const ConvexPolyhedron& p, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<Vec3> out;
  for (int i = 0; i < 6000; ++i) {
    const bool near_centre = i % 2 == 1;
    const Vec3 c = near_centre ? p.incenter() : p.centroid();
    const double r = near_centre ? 0.3 * p.inradius() : p.circumradius();
    const Vec3 x = c + r * Vec3(u(rng), u(rng), u(rng));
    if (p.contains(x)) out.push_back(x);
  }
  return out;
}

// The property the distance-potential kernel relies on: a point of p that is no deeper below
// face k than below any listed neighbour of k is no deeper below k than below any face at all.
void expectNeighboursDecideTheRegion(const ConvexPolyhedron& p, std::uint64_t seed) {
  const FaceRegions& r = p.faceRegions();
  const int m = static_cast<int>(p.faces().size());
  ASSERT_EQ(static_cast<int>(r.begin.size()), m + 1);
  const double tol = 1e-12 * p.lengthScale();
  int decided = 0;
  for (const Vec3& x : insidePoints(p, seed)) {
    double nearest = INFINITY;
    for (int l = 0; l < m; ++l) nearest = std::min(nearest, depth(p, l, x));
    for (int k = 0; k < m; ++k) {
      bool below_neighbours = true;
      for (int l : r.of(k)) below_neighbours = below_neighbours && depth(p, k, x) <= depth(p, l, x);
      if (!below_neighbours) continue;
      ++decided;
      EXPECT_LE(depth(p, k, x), nearest + tol) << "face " << k;
    }
  }
  EXPECT_GT(decided, 1000);
}

TEST(FaceRegions, CubeFacesBorderTheirFourSideFaces) {
  const auto cube = ConvexPolyhedron::fromPoints(shapes::cube(1.0));
  const FaceRegions& r = cube.faceRegions();
  for (const Edge& e : cube.edges()) {
    EXPECT_TRUE(lists(r, e.f0, e.f1));
    EXPECT_TRUE(lists(r, e.f1, e.f0));
  }
  for (int k = 0; k < 6; ++k) {
    EXPECT_GE(r.of(k).size(), 4u);
    EXPECT_FALSE(lists(r, k, k));
  }
  expectNeighboursDecideTheRegion(cube, 1);
}

TEST(FaceRegions, NeighboursDecideTheRegionOnIrregularAndRandomShapes) {
  std::vector<std::vector<Vec3>> clouds = {
      {{0, 0, 0}, {1.6, 0, 0}, {0.3, 1.1, 0}, {0.5, 0.4, 0.9}},  // irregular tetrahedron
      shapes::box({-2, -0.5, -0.3}, {2, 0.5, 0.3}),              // inner domain a segment
      shapes::box({-1, -1, -0.25}, {1, 1, 0.25}),                // inner domain a square
      shapes::ridgePrism({-1, 0, 0}, {1, 0, 0}, 0.5, 1.0),       // wedge
  };
  for (int n : {8, 15, 40}) clouds.push_back(shapes::randomConvex(n, 300 + n, {1, 0.7, 0.5}, 0.2));
  std::uint64_t seed = 10;
  for (const auto& cloud : clouds) {
    const auto p = ConvexPolyhedron::fromPoints(cloud);
    // Faces sharing an edge always border each other (their bisector passes through the edge).
    for (const Edge& e : p.edges()) EXPECT_TRUE(lists(p.faceRegions(), e.f0, e.f1));
    expectNeighboursDecideTheRegion(p, ++seed);
  }
}

TEST(FaceRegions, SameUnderRigidMotionAndUnitAndSharedByCopies) {
  const auto p = ConvexPolyhedron::fromPoints(shapes::randomConvex(30, 5, {1, 0.8, 0.6}, 0.2));
  const Mat3 turn = Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized()).toRotationMatrix();
  // Built from the moved points, not copied: computed afresh.
  std::vector<Vec3> moved, small;
  for (const Vec3& v : p.vertices()) {
    moved.push_back(turn * v + Vec3(1e3, -2e3, 5e2));
    small.push_back(1e-3 * v);
  }
  const auto q = ConvexPolyhedron::fromPoints(moved);
  const auto s = ConvexPolyhedron::fromPoints(small);
  const FaceRegions& r = p.faceRegions();
  EXPECT_EQ(q.faceRegions().begin, r.begin);
  EXPECT_EQ(q.faceRegions().neighbours, r.neighbours);
  EXPECT_EQ(s.faceRegions().neighbours, r.neighbours);
  expectNeighboursDecideTheRegion(q, 3);
  expectNeighboursDecideTheRegion(s, 4);
  // Copies made after the first use share it.
  const ConvexPolyhedron copy = p;
  const ConvexPolyhedron turned = p.transformed(turn, Vec3(1, 2, 3));
  EXPECT_EQ(&copy.faceRegions(), &r);
  EXPECT_EQ(&turned.faceRegions(), &r);
}

}  // namespace
}  // namespace polydem::geometry
