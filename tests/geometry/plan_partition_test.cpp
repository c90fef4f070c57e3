// A triangulated surface in plan (geometry/plan_triangulation.h, plan_partition.h): the Delaunay
// triangulation covers the points' hull once (a regular grid too, whose squares have four points
// on one circle) and refuses two points at one place and points on one line; the cells tile the
// whole plane (a uniform pressure on a polygon reaching far beyond the hull gives its area); the
// surface is the triangles' planes inside the hull and the height of the hull's nearest point
// outside it, against an independent evaluation; the pressure below it on a tilted face that
// crosses several triangles, the hull and the line p = 0 matches a dense quadrature; points on one
// plane give that plane's resultant to round-off; at scales 1e-3 and 1e3.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "polydem/geometry/plan_partition.h"
#include "polydem/geometry/plan_triangulation.h"

namespace polydem::geometry {
namespace {

constexpr double kGamma = 9810.0;  // N/m^3

// A folded surface: eight points, heights in [-1, 2] m, scaled by `s`.
struct Surface {
  std::vector<PlanPoint> points;
  std::vector<double> z;
};

Surface folded(double s) {
  Surface out;
  const double xy[8][3] = {{0, 0, 0.0},   {4, 0, -1.0},  {4, 3, 0.5},    {0, 3, 2.0},
                           {2, 1.5, 1.5}, {1, 0.5, 0.2}, {3, 2.5, -0.5}, {2, -0.5, 0.0}};
  for (const auto& p : xy) {
    out.points.push_back({s * p[0], s * p[1]});
    out.z.push_back(s * p[2]);
  }
  return out;
}

double triangleArea(const PlanPoint& a, const PlanPoint& b, const PlanPoint& c) {
  return 0.5 * orient(a, b, c);
}

// The surface's height at (x, y), found without the partition: barycentric interpolation in a
// triangle that contains the point, or, outside all, the height at the nearest point of the
// hull's edges (the triangles' edges used once).
double reference(const Surface& s, const std::vector<PlanTriangle>& tris, double x, double y) {
  const PlanPoint q{x, y};
  const double scale = 1e-12;
  for (const auto& t : tris) {
    const auto &a = s.points[t[0]], &b = s.points[t[1]], &c = s.points[t[2]];
    const double area = triangleArea(a, b, c);
    const double wa = triangleArea(q, b, c) / area, wb = triangleArea(a, q, c) / area;
    const double wc = 1.0 - wa - wb;
    if (wa >= -scale && wb >= -scale && wc >= -scale) {
      return wa * s.z[t[0]] + wb * s.z[t[1]] + wc * s.z[t[2]];
    }
  }
  double best = std::numeric_limits<double>::infinity(), height = 0.0;
  for (const auto& t : tris) {
    for (int e = 0; e < 3; ++e) {
      const int i = t[e], j = t[(e + 1) % 3];
      bool shared = false;
      for (const auto& u : tris) {
        for (int f = 0; f < 3; ++f) shared |= u[f] == j && u[(f + 1) % 3] == i;
      }
      if (shared) continue;
      const auto &a = s.points[i], &b = s.points[j];
      const double dx = b[0] - a[0], dy = b[1] - a[1];
      double u = ((x - a[0]) * dx + (y - a[1]) * dy) / (dx * dx + dy * dy);
      u = std::clamp(u, 0.0, 1.0);
      const double d = std::hypot(x - a[0] - u * dx, y - a[1] - u * dy);
      if (d < best) best = d, height = s.z[i] + u * (s.z[j] - s.z[i]);
    }
  }
  return height;
}

std::vector<int> indices(std::size_t n) {
  std::vector<int> out(n);
  for (std::size_t i = 0; i < n; ++i) out[i] = static_cast<int>(i);
  return out;
}

// p = gamma (z_s - z) about `origin`, one per cell.
std::vector<LinearPressure> cellPressures(const PlanPartition& part, const Surface& s,
                                          const Vec3& origin) {
  std::vector<LinearPressure> out;
  for (std::size_t c = 0; c < part.cellCount(); ++c) {
    const PlanPlane p = part.plane(c, s.z);
    out.push_back({origin, kGamma * (p.at(origin.x(), origin.y()) - origin.z()),
                   kGamma * Vec3(p.slope_x, p.slope_y, -1.0)});
  }
  return out;
}

class PlanPartitionScale : public ::testing::TestWithParam<double> {};

TEST_P(PlanPartitionScale, DelaunayCoversTheHullOnce) {
  const double s = GetParam();
  const Surface f = folded(s);
  const auto t = delaunayTriangulation(f.points);
  ASSERT_TRUE(t.error.empty()) << t.error;
  EXPECT_EQ(t.triangles.size(), 9u);  // 2 n - 2 - h, n = 8 points, h = 5 on the hull
  double area = 0.0;
  for (const auto& tri : t.triangles) {
    const double a = triangleArea(f.points[tri[0]], f.points[tri[1]], f.points[tri[2]]);
    EXPECT_GT(a, 0.0);
    area += a;
  }
  // The hull: (0,0), (2,-0.5), (4,0), (4,3), (0,3).
  EXPECT_NEAR(area, s * s * (12.0 + 0.5 * 4 * 0.5), 1e-12 * s * s * 12);
  // Empty circumcircles: no point strictly inside any triangle's circle.
  for (const auto& tri : t.triangles) {
    const auto &a = f.points[tri[0]], &b = f.points[tri[1]], &c = f.points[tri[2]];
    for (std::size_t k = 0; k < f.points.size(); ++k) {
      const auto& d = f.points[k];
      const double ax = a[0] - d[0], ay = a[1] - d[1], bx = b[0] - d[0], by = b[1] - d[1];
      const double cx = c[0] - d[0], cy = c[1] - d[1];
      const double det = (ax * ax + ay * ay) * (bx * cy - by * cx) -
                         (bx * bx + by * by) * (ax * cy - ay * cx) +
                         (cx * cx + cy * cy) * (ax * by - ay * bx);
      EXPECT_LE(det, 1e-9 * std::pow(4 * s, 4)) << "point " << k;
    }
  }
}

TEST(PlanTriangulation, GridAndRefusals) {
  std::vector<PlanPoint> grid;
  for (int i = 0; i < 4; ++i) {
    for (int j = 0; j < 3; ++j) grid.push_back({1.0 * i, 0.5 * j});
  }
  const auto t = delaunayTriangulation(grid);
  ASSERT_TRUE(t.error.empty()) << t.error;
  EXPECT_EQ(t.triangles.size(), 12u);
  double area = 0.0;
  for (const auto& tri : t.triangles)
    area += triangleArea(grid[tri[0]], grid[tri[1]], grid[tri[2]]);
  EXPECT_NEAR(area, 3.0, 1e-14);
  EXPECT_EQ(delaunayTriangulation(std::vector<PlanPoint>{{0, 0}, {1, 0}, {2, 0}, {3, 0}}).error,
            "the points lie on one line in plan (x, y): they give no surface");
  EXPECT_EQ(delaunayTriangulation(std::vector<PlanPoint>{{0, 0}, {1, 0}, {0, 1}, {1, 0}}).error,
            "points 2 and 4 lie at one place in plan (x, y)");
}

TEST_P(PlanPartitionScale, CellsTileThePlane) {
  const double s = GetParam();
  const Surface f = folded(s);
  const PlanPartition part(f.points, delaunayTriangulation(f.points).triangles);
  // A uniform pressure of 1 Pa on a square far larger than the hull, and on one inside a cell.
  const std::vector<Vec3> square{Vec3(-20 * s, -20 * s, 0), Vec3(30 * s, -20 * s, 0),
                                 Vec3(30 * s, 25 * s, 0), Vec3(-20 * s, 25 * s, 0)};
  const std::vector<LinearPressure> unit(part.cellCount(), {Vec3::Zero(), 1.0, Vec3::Zero()});
  const auto r = part.resultant(square, indices(4), Vec3::UnitZ(), unit);
  EXPECT_NEAR(r.load, 50.0 * 45.0 * s * s, 1e-13 * 50.0 * 45.0 * s * s);
}

TEST_P(PlanPartitionScale, SurfaceInsideAndBeyondTheHull) {
  const double s = GetParam();
  const Surface f = folded(s);
  const auto tris = delaunayTriangulation(f.points).triangles;
  const PlanPartition part(f.points, tris);
  for (int i = 0; i <= 60; ++i) {
    for (int j = 0; j <= 50; ++j) {
      const double x = s * (-3.0 + 0.17 * i), y = s * (-4.0 + 0.21 * j);
      const double got = part.plane(part.cellAt(x, y), f.z).at(x, y);
      EXPECT_NEAR(got, reference(f, tris, x, y), 1e-12 * s * 10) << x << ", " << y;
    }
  }
}

// A pentagon in a tilted plane through the surface's hull, below the surface in part.
std::vector<Vec3> tiltedFace(double s) {
  const Vec3 c(2.2, 1.4, 0.3), u = Vec3(1, 0.2, 0.4).normalized();
  const Vec3 n = Vec3(-0.3, 0.5, 1).normalized();
  const Vec3 v = n.cross(u);
  std::vector<Vec3> out;
  for (int k = 0; k < 5; ++k) {
    const double a = 2 * M_PI * k / 5;
    out.push_back(s * (c + 2.6 * std::cos(a) * u + 2.0 * std::sin(a) * v));
  }
  return out;  // counter-clockwise about n
}

TEST_P(PlanPartitionScale, TiltedFaceAgainstDenseQuadrature) {
  const double s = GetParam();
  const Surface f = folded(s);
  const auto tris = delaunayTriangulation(f.points).triangles;
  const PlanPartition part(f.points, tris);
  const auto face = tiltedFace(s);
  const Vec3 normal = (face[1] - face[0]).cross(face[2] - face[0]).normalized();
  const Vec3 origin = s * Vec3(1.0, 2.0, -1.0);
  const auto r = part.resultant(face, indices(5), normal, cellPressures(part, f, origin));
  // Midpoint rule on a fine subdivision of the face's fan triangles: each cut into m^2.
  const int m = 300;
  double load = 0.0, area = 0.0;
  Vec3 moment = Vec3::Zero();
  bool dry = false, wet = false;
  for (int k = 1; k + 1 < 5; ++k) {
    const Vec3 &a = face[0], e1 = (face[k] - a) / m, e2 = (face[k + 1] - a) / m;
    const double da = 0.5 * e1.cross(e2).norm();
    for (int i = 0; i < m; ++i) {
      for (int j = 0; i + j < m; ++j) {
        for (int up = 0; up < (i + j + 1 < m ? 2 : 1); ++up) {
          const Vec3 x = up ? a + (i + 2.0 / 3) * e1 + (j + 2.0 / 3) * e2
                            : a + (i + 1.0 / 3) * e1 + (j + 1.0 / 3) * e2;
          const double p = kGamma * (reference(f, tris, x.x(), x.y()) - x.z());
          area += da;
          (p > 0 ? wet : dry) = true;
          if (p <= 0) continue;
          load += p * da;
          moment += (x - origin).cross(-p * da * normal);
        }
      }
    }
  }
  ASSERT_TRUE(wet && dry);  // the face crosses p = 0
  const double scale = kGamma * s * s * s;
  EXPECT_NEAR(r.load, load, 2e-5 * load);
  EXPECT_NEAR((r.force + load * normal).norm(), 0.0, 2e-5 * load);
  EXPECT_NEAR((r.moment - moment).norm(), 0.0, 2e-5 * moment.norm() + 1e-9 * scale * s);
}

TEST_P(PlanPartitionScale, PointsOnOnePlaneGiveThePlane) {
  const double s = GetParam();
  Surface f = folded(s);
  const PlanPlane plane{0.5 * s, 0.2 * s, 0.8 * s, -0.3, 0.45};
  for (std::size_t k = 0; k < f.points.size(); ++k)
    f.z[k] = plane.at(f.points[k][0], f.points[k][1]);
  const PlanPartition part(f.points, delaunayTriangulation(f.points).triangles);
  // A face inside the hull, crossing triangles and p = 0.
  std::vector<Vec3> face;
  for (const Vec3& x : tiltedFace(s))
    face.push_back(Vec3(2 * s, 1.5 * s, 0) + 0.45 * (x - Vec3(2.2 * s, 1.4 * s, 0.3 * s)) +
                   Vec3(0, 0, 0.6 * s));
  const Vec3 normal = (face[1] - face[0]).cross(face[2] - face[0]).normalized();
  const Vec3 origin = s * Vec3(2.0, 1.0, 0.0);
  const LinearPressure one{origin, kGamma * (plane.at(origin.x(), origin.y()) - origin.z()),
                           kGamma * Vec3(plane.slope_x, plane.slope_y, -1.0)};
  const auto want = pressureResultant(face, indices(5), normal, one);
  const auto got = part.resultant(face, indices(5), normal, cellPressures(part, f, origin));
  const std::vector<LinearPressure> unit(1, {origin, 1.0, Vec3::Zero()});
  const double area = pressureResultant(face, indices(5), normal, unit[0]).load;
  ASSERT_GT(want.wetted_area, 0.05 * area);  // partly wet,
  ASSERT_LT(want.wetted_area, 0.95 * area);  // partly dry
  EXPECT_NEAR(got.load, want.load, 1e-12 * want.load);
  EXPECT_NEAR((got.force - want.force).norm(), 0.0, 1e-12 * want.load);
  EXPECT_NEAR((got.moment - want.moment).norm(), 0.0, 1e-12 * want.load * s);
}

INSTANTIATE_TEST_SUITE_P(Scales, PlanPartitionScale, ::testing::Values(1e-3, 1.0, 1e3));

}  // namespace
}  // namespace polydem::geometry
