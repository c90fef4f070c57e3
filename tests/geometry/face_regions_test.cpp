// The nearest-face partition (face_regions.h): the neighbours listed for a face's region are
// enough to tell whether a point lies in it, on regular, irregular and random polyhedra, at any
// scale and pose; copies share the partition.
#include "polydem/geometry/face_regions.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
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

// The area of the convex hull of points lying in one plane with normal w.
double hullArea(std::vector<Vec3> points, const Vec3& w) {
  if (points.size() < 3) return 0.0;
  Vec3 centre = Vec3::Zero();
  for (const Vec3& x : points) centre += x;
  centre /= static_cast<double>(points.size());
  const Vec3 e1 = w.unitOrthogonal(), e2 = w.cross(e1);
  std::sort(points.begin(), points.end(), [&](const Vec3& a, const Vec3& b) {
    return std::atan2((a - centre).dot(e2), (a - centre).dot(e1)) <
           std::atan2((b - centre).dot(e2), (b - centre).dot(e1));
  });
  double twice = 0.0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    twice += (points[i] - centre).cross(points[(i + 1) % points.size()] - centre).dot(w);
  }
  return 0.5 * std::abs(twice);
}

// The located regions (corners in affine coordinates, facets as masks of corners) of p: every
// corner lies in its region, the regions' hulls fill p, and each facet's corners lie on the
// bisector and span the same polygon as the other region's corners of that facet.
void expectRegionsLocated(const ConvexPolyhedron& p) {
  const FaceRegions& r = p.faceRegions();
  const int m = static_cast<int>(p.faces().size());
  const double tol = 1e-9 * p.lengthScale();
  const auto& v = p.vertices();
  const Vec3& v0 = v[r.basis[0]];
  auto where = [&](const Vec3& a) {
    return Vec3(v0 + a.x() * (v[r.basis[1]] - v0) + a.y() * (v[r.basis[2]] - v0) +
                a.z() * (v[r.basis[3]] - v0));
  };
  auto corners = [&](int k) {
    std::vector<Vec3> out;
    for (int i = r.corner_begin[k]; i < r.corner_begin[k + 1]; ++i)
      out.push_back(where(r.corners[i]));
    return out;
  };
  auto facet = [&](int k, int l) {
    const auto n = r.of(k);
    const std::uint64_t mask =
        r.facets[r.begin[k] + (std::find(n.begin(), n.end(), l) - n.begin())];
    std::vector<Vec3> out;
    const auto c = corners(k);
    for (std::size_t i = 0; i < c.size(); ++i) {
      if (mask >> i & 1) out.push_back(c[i]);
    }
    return out;
  };
  ASSERT_EQ(static_cast<int>(r.corner_begin.size()), m + 1);
  ASSERT_EQ(r.facets.size(), r.neighbours.size());
  double volume = 0.0;
  for (int k = 0; k < m; ++k) {
    const auto c = corners(k);
    ASSERT_LE(c.size(), static_cast<std::size_t>(FaceRegions::kMaskedCorners)) << "face " << k;
    for (const Vec3& x : c) {
      EXPECT_GE(depth(p, k, x), -tol);
      for (int l = 0; l < m; ++l) EXPECT_LE(depth(p, k, x), depth(p, l, x) + tol) << k << " " << l;
    }
    volume += ConvexPolyhedron::fromPoints(c).volume();
    for (int l : r.of(k)) {
      ASSERT_TRUE(lists(r, l, k)) << k << " " << l;
      const auto mine = facet(k, l);
      EXPECT_FALSE(mine.empty()) << k << " " << l;
      for (const Vec3& x : mine) EXPECT_NEAR(depth(p, k, x), depth(p, l, x), tol) << k << " " << l;
      // Seen from either side, the facet is the same polygon (either may have extra corners on
      // its edges, where a third region touches it).
      const Vec3 w = (p.faces()[l].normal - p.faces()[k].normal).normalized();
      EXPECT_NEAR(hullArea(mine, w), hullArea(facet(l, k), w), tol * p.lengthScale())
          << k << " " << l;
    }
  }
  EXPECT_NEAR(volume, p.volume(), 1e-9 * p.volume());
}

TEST(FaceRegions, RegionCornersFillTheShapeAndFacetsLieOnTheBisectors) {
  std::vector<std::vector<Vec3>> clouds = {
      shapes::cube(1.0),
      {{0, 0, 0}, {1.6, 0, 0}, {0.3, 1.1, 0}, {0.5, 0.4, 0.9}},
      shapes::box({-2, -0.5, -0.3}, {2, 0.5, 0.3}),
      shapes::ridgePrism({-1, 0, 0}, {1, 0, 0}, 0.5, 1.0),
  };
  for (int n : {8, 15, 40}) clouds.push_back(shapes::randomConvex(n, 300 + n, {1, 0.7, 0.5}, 0.2));
  for (const auto& cloud : clouds) expectRegionsLocated(ConvexPolyhedron::fromPoints(cloud));
  // Computed before a move and a change of unit, the affine coordinates still hold.
  const auto p = ConvexPolyhedron::fromPoints(shapes::randomConvex(30, 5, {1, 0.8, 0.6}, 0.2));
  p.faceRegions();
  const Mat3 turn = Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized()).toRotationMatrix();
  expectRegionsLocated(p.transformed(turn, Vec3(1e3, -2e3, 5e2)).scaled(1e-3));
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
