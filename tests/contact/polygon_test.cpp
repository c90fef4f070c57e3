// geometry/polygon.h against hand-computed answers: hull ordering, point in polygon, and the
// intersection of convex polygons (nested, disjoint, touching, identical, sliver, general) with its
// area and centroid.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "polydem/geometry/polygon.h"

namespace polydem::geometry {
namespace {

std::vector<Vec2> rectangle(double x0, double y0, double x1, double y1) {
  return {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}};
}

/// Regular n-gon of circumradius r about c, counter-clockwise, first corner at angle phase.
std::vector<Vec2> regular(int n, double r, const Vec2& c, double phase = 0.0) {
  std::vector<Vec2> p;
  for (int k = 0; k < n; ++k) {
    const double a = phase + 2.0 * kPi * k / n;
    p.push_back(c + r * Vec2(std::cos(a), std::sin(a)));
  }
  return p;
}

AreaCentroid intersection(const std::vector<Vec2>& p, const std::vector<Vec2>& q) {
  std::vector<Vec2> out, scratch;
  intersectConvex(p, q, out, scratch);
  return areaCentroid(out);
}

TEST(Polygon, HullDropsInteriorRepeatedAndCollinearPointsAndTurnsCounterClockwise) {
  std::vector<Vec2> points = {{1, 1},   {0, 0}, {0.5, 0.5}, {1, 0}, {0, 1},
                              {0.5, 0}, {1, 1}, {0, 0.5},   {0, 0}};
  std::vector<Vec2> hull;
  convexHull(points, hull);
  const std::vector<Vec2> expected = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  ASSERT_EQ(hull.size(), expected.size());
  for (std::size_t i = 0; i < hull.size(); ++i) EXPECT_EQ(hull[i], expected[i]);
}

TEST(Polygon, HullOfTooFewDistinctPoints) {
  std::vector<Vec2> hull;
  std::vector<Vec2> one = {{2, 3}, {2, 3}, {2, 3}};
  convexHull(one, hull);
  EXPECT_LT(hull.size(), 3u);
  EXPECT_EQ(areaCentroid(hull).area, 0.0);
  std::vector<Vec2> line = {{0, 0}, {1, 1}, {2, 2}, {0.5, 0.5}};
  convexHull(line, hull);
  EXPECT_EQ(hull.size(), 2u);
  std::vector<Vec2> none;
  convexHull(none, hull);
  EXPECT_TRUE(hull.empty());
}

TEST(Polygon, ContainsPointKeissarEq29) {
  const auto square = rectangle(0, 0, 1, 1);
  EXPECT_TRUE(containsPoint(square, {0.5, 0.5}));
  EXPECT_TRUE(containsPoint(square, {1.0, 0.5}));  // on an edge
  EXPECT_TRUE(containsPoint(square, {0.0, 0.0}));  // a corner
  EXPECT_FALSE(containsPoint(square, {1.0 + 1e-12, 0.5}));
  EXPECT_TRUE(containsPoint(square, {1.0 + 1e-12, 0.5}, 1e-11));
  EXPECT_FALSE(containsPoint(square, {-0.1, 2.0}));
}

TEST(Polygon, AreaAndCentroidOfATriangleAndASquare) {
  const std::vector<Vec2> triangle = {{0, 0}, {3, 0}, {0, 3}};
  const AreaCentroid t = areaCentroid(triangle);
  EXPECT_DOUBLE_EQ(t.area, 4.5);
  EXPECT_NEAR((t.centroid - Vec2(1, 1)).norm(), 0.0, 1e-15);
  const AreaCentroid cw = areaCentroid(std::vector<Vec2>{{0, 0}, {0, 3}, {3, 0}});
  EXPECT_DOUBLE_EQ(cw.area, -4.5);  // clockwise: negative, same centroid
  EXPECT_NEAR((cw.centroid - Vec2(1, 1)).norm(), 0.0, 1e-15);
}

TEST(Polygon, CentroidFarFromTheOriginKeepsItsDigits) {
  // Summed about the first corner: a unit square at 1e8 keeps its centroid to round-off of 1e8.
  const Vec2 far(1e8, -3e8);
  const AreaCentroid m = areaCentroid(rectangle(far.x(), far.y(), far.x() + 1, far.y() + 1));
  EXPECT_NEAR(m.area, 1.0, 1e-7);
  EXPECT_NEAR(m.centroid.x(), far.x() + 0.5, 1e-7);
  EXPECT_NEAR(m.centroid.y(), far.y() + 0.5, 1e-7);
}

TEST(Polygon, NestedGivesTheInnerPolygon) {
  const auto outer = rectangle(-2, -2, 3, 3);
  const auto inner = regular(7, 0.5, {0.3, 0.1}, 0.2);
  const AreaCentroid expected = areaCentroid(inner);
  for (const auto& m : {intersection(inner, outer), intersection(outer, inner)}) {
    EXPECT_NEAR(m.area, expected.area, 1e-14);
    EXPECT_NEAR((m.centroid - expected.centroid).norm(), 0.0, 1e-14);
  }
}

TEST(Polygon, DisjointGivesNothing) {
  std::vector<Vec2> out, scratch;
  intersectConvex(rectangle(0, 0, 1, 1), rectangle(2, 0, 3, 1), out, scratch);
  EXPECT_TRUE(out.empty());
  intersectConvex(regular(5, 1, {0, 0}), regular(6, 1, {2.5, 0.5}), out, scratch);
  EXPECT_TRUE(out.empty());
}

TEST(Polygon, TouchingGivesZeroArea) {
  // Sharing an edge, and sharing only a corner.
  EXPECT_NEAR(intersection(rectangle(0, 0, 1, 1), rectangle(1, 0, 2, 1)).area, 0.0, 1e-15);
  EXPECT_NEAR(intersection(rectangle(0, 0, 1, 1), rectangle(1, 1, 2, 2)).area, 0.0, 1e-15);
  EXPECT_NEAR(intersection(rectangle(1, 1, 2, 2), rectangle(0, 0, 1, 1)).area, 0.0, 1e-15);
}

TEST(Polygon, IdenticalGivesItself) {
  const auto p = regular(6, 1.3, {0.2, -0.7}, 0.1);
  const AreaCentroid expected = areaCentroid(p);
  const AreaCentroid m = intersection(p, p);
  EXPECT_NEAR(m.area, expected.area, 1e-14);
  EXPECT_NEAR((m.centroid - expected.centroid).norm(), 0.0, 1e-14);
}

TEST(Polygon, SliverOverlap) {
  // Two rectangles overlapping in a strip w = 2^-30 (about 1e-9, exact in binary) wide and 2
  // long: area 2 w, centroid in the middle of the strip.
  const double w = std::ldexp(1.0, -30);
  const auto a = rectangle(0, -1, 1, 1);
  const auto b = rectangle(1 - w, -3, 5, 1);
  const AreaCentroid m = intersection(a, b);
  EXPECT_NEAR(m.area, 2 * w, 1e-15 * w);
  EXPECT_NEAR(m.centroid.x(), 1 - 0.5 * w, 1e-16);
  EXPECT_NEAR(m.centroid.y(), 0.0, 1e-15);
}

TEST(Polygon, TriangleCutBySquare) {
  // Hand-computed: the square [0.5, 1.5]^2 minus the corner above x + y = 2 is the triangle
  // (0.5, 0.5), (1.5, 0.5), (0.5, 1.5): area 1/2, centroid (5/6, 5/6).
  const std::vector<Vec2> triangle = {{0, 0}, {2, 0}, {0, 2}};
  const auto square = rectangle(0.5, 0.5, 1.5, 1.5);
  for (const auto& m : {intersection(triangle, square), intersection(square, triangle)}) {
    EXPECT_NEAR(m.area, 0.5, 1e-15);
    EXPECT_NEAR((m.centroid - Vec2(5.0 / 6.0, 5.0 / 6.0)).norm(), 0.0, 1e-15);
  }
}

TEST(Polygon, SquareAndTurnedSquareGiveTheRegularOctagon) {
  // The square [-1, 1]^2 and itself turned 45 degrees meet in the regular octagon of inradius 1:
  // area 8 tan(pi / 8).
  const auto square = rectangle(-1, -1, 1, 1);
  const auto turned = regular(4, std::sqrt(2.0), {0, 0}, 0.0);  // corners on the axes
  const AreaCentroid m = intersection(square, turned);
  EXPECT_NEAR(m.area, 8.0 * std::tan(kPi / 8.0), 1e-14);
  EXPECT_NEAR(m.centroid.norm(), 0.0, 1e-15);
}

TEST(Polygon, OverlappingRectanglesOffCentre) {
  // [0, 4] x [0, 2] and [3, 6] x [-1, 1] share [3, 4] x [0, 1].
  const AreaCentroid m = intersection(rectangle(0, 0, 4, 2), rectangle(3, -1, 6, 1));
  EXPECT_NEAR(m.area, 1.0, 1e-15);
  EXPECT_NEAR((m.centroid - Vec2(3.5, 0.5)).norm(), 0.0, 1e-15);
}

TEST(Polygon, ClipByHalfPlanesMatchesClipByEdges) {
  const auto p = regular(9, 1.0, {0.1, 0.2}, 0.3);
  const auto q = regular(5, 0.9, {0.6, -0.1}, 1.1);
  std::vector<HalfPlane> planes;
  for (std::size_t i = 0; i < q.size(); ++i) planes.push_back(leftOf(q[i], q[(i + 1) % q.size()]));
  std::vector<Vec2> out, scratch;
  clipByHalfPlanes(p, planes, out, scratch);
  const AreaCentroid by_planes = areaCentroid(out);
  const AreaCentroid by_edges = intersection(p, q);
  EXPECT_GT(by_planes.area, 0.1);
  EXPECT_NEAR(by_planes.area, by_edges.area, 1e-15);
  EXPECT_NEAR((by_planes.centroid - by_edges.centroid).norm(), 0.0, 1e-15);
  // Every corner of the result lies in both polygons.
  for (const Vec2& c : out) {
    EXPECT_TRUE(containsPoint(p, c, 1e-14));
    EXPECT_TRUE(containsPoint(q, c, 1e-14));
  }
}

TEST(Polygon, ClipPolygonWithARepeatedCornerIgnoresItsZeroEdge) {
  auto q = rectangle(0, 0, 1, 1);
  q.insert(q.begin() + 2, q[1]);  // corner (1, 0) twice
  const AreaCentroid m = intersection(rectangle(-1, -1, 0.5, 0.5), q);
  EXPECT_NEAR(m.area, 0.25, 1e-15);
  EXPECT_NEAR((m.centroid - Vec2(0.25, 0.25)).norm(), 0.0, 1e-15);
}

}  // namespace
}  // namespace polydem::geometry
