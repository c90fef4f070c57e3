// Volume, centroid, inertia and the circumscribed / inscribed spheres against closed forms, and
// against an independent decomposition on irregular polyhedra.
#include <gtest/gtest.h>

#include <cmath>

#include "polydem/geometry/convex_polyhedron.h"
#include "polydem/geometry/shapes.h"
#include "polyhedron_checks.h"

namespace polydem::geometry {
namespace {

using shapes::Platonic;

/// |a - b| <= rel * |b| for matrices, with |.| the Frobenius norm.
void expectMatrixNear(const Mat3& a, const Mat3& b, double rel) {
  EXPECT_LE((a - b).norm(), rel * b.norm()) << "got\n" << a << "\nexpected\n" << b;
}

Mat3 diag(double x, double y, double z) {
  return Vec3(x, y, z).asDiagonal();
}

TEST(MassProperties, Cube) {
  const double a = 0.7;
  const auto cube =
      ConvexPolyhedron::fromPoints(shapes::boxAround(Vec3(1, 2, 3), Vec3::Constant(a / 2)));
  const double v = a * a * a;
  EXPECT_NEAR(cube.volume(), v, 1e-15 * v);
  EXPECT_LT((cube.centroid() - Vec3(1, 2, 3)).norm(), 1e-15);
  expectMatrixNear(cube.inertia(), Mat3::Identity() * v * a * a / 6.0, 1e-14);
  EXPECT_NEAR(cube.circumradius(), a * std::sqrt(3.0) / 2.0, 1e-15);
  EXPECT_NEAR(cube.inradius(), a / 2.0, 1e-14);
  EXPECT_LT((cube.incenter() - Vec3(1, 2, 3)).norm(), 1e-13);
  EXPECT_DOUBLE_EQ(cube.lengthScale(), 2.0 * cube.circumradius());
}

TEST(MassProperties, SymmetricBoxHasItsCentroidExactlyAtTheCentre) {
  const auto box =
      ConvexPolyhedron::fromPoints(shapes::boxAround(Vec3::Zero(), Vec3(0.3, 0.7, 1.1)));
  EXPECT_EQ(box.centroid(), Vec3::Zero());
  EXPECT_EQ(box.inertia()(0, 1), 0.0);
  EXPECT_EQ(box.inertia()(0, 2), 0.0);
  EXPECT_EQ(box.inertia()(1, 2), 0.0);
}

TEST(MassProperties, Cuboid) {
  const double a = 1.0, b = 2.5, c = 0.4;
  const auto box =
      ConvexPolyhedron::fromPoints(shapes::box(Vec3(-1, 0, 2), Vec3(-1 + a, b, 2 + c)));
  const double v = a * b * c;
  EXPECT_NEAR(box.volume(), v, 1e-15 * v);
  EXPECT_LT((box.centroid() - Vec3(-1 + a / 2, b / 2, 2 + c / 2)).norm(), 1e-15);
  expectMatrixNear(box.inertia(), v / 12.0 * diag(b * b + c * c, a * a + c * c, a * a + b * b),
                   1e-14);
  EXPECT_NEAR(box.inradius(), c / 2, 1e-14);
  EXPECT_NEAR(box.incenter().z(), 2 + c / 2, 1e-14);
  EXPECT_NEAR(box.circumradius(), 0.5 * std::sqrt(a * a + b * b + c * c), 1e-15);
}

TEST(MassProperties, RegularTetrahedron) {
  const double a = 1.3;
  const auto tet = ConvexPolyhedron::fromPoints(shapes::tetrahedron(a));
  const double v = a * a * a / (6.0 * std::sqrt(2.0));
  EXPECT_NEAR(tet.volume(), v, 1e-15 * v);
  EXPECT_LT(tet.centroid().norm(), 1e-15);
  expectMatrixNear(tet.inertia(), Mat3::Identity() * v * a * a / 20.0, 1e-14);
  EXPECT_NEAR(tet.inradius(), a / (2.0 * std::sqrt(6.0)), 1e-14);
  EXPECT_LT(tet.incenter().norm(), 1e-14);
  EXPECT_NEAR(tet.circumradius(), a * std::sqrt(6.0) / 4.0, 1e-15);
}

TEST(MassProperties, Octahedron) {
  const double a = 0.9;
  const auto oct = ConvexPolyhedron::fromPoints(shapes::octahedron(a));
  const double v = std::sqrt(2.0) / 3.0 * a * a * a;
  EXPECT_NEAR(oct.volume(), v, 1e-15 * v);
  expectMatrixNear(oct.inertia(), Mat3::Identity() * v * a * a / 10.0, 1e-14);
  EXPECT_NEAR(oct.inradius(), a / std::sqrt(6.0), 1e-14);
  EXPECT_NEAR(oct.circumradius(), a / std::sqrt(2.0), 1e-15);
}

TEST(MassProperties, IcosahedronAndDodecahedron) {
  const double a = 1.1, phi = 0.5 * (1.0 + std::sqrt(5.0));
  const auto ico = ConvexPolyhedron::fromPoints(shapes::icosahedron(a));
  const double vi = 5.0 * (3.0 + std::sqrt(5.0)) / 12.0 * a * a * a;
  EXPECT_NEAR(ico.volume(), vi, 1e-14 * vi);
  expectMatrixNear(ico.inertia(), Mat3::Identity() * vi * a * a * phi * phi / 10.0, 1e-14);
  EXPECT_NEAR(ico.inradius(), a * phi * phi / (2.0 * std::sqrt(3.0)), 1e-14);
  EXPECT_NEAR(ico.circumradius(), a * shapes::platonicCircumradiusPerEdge(Platonic::kIcosahedron),
              1e-14);

  const auto dod = ConvexPolyhedron::fromPoints(shapes::dodecahedron(a));
  const double vd = (15.0 + 7.0 * std::sqrt(5.0)) / 4.0 * a * a * a;
  EXPECT_NEAR(dod.volume(), vd, 1e-14 * vd);
  expectMatrixNear(dod.inertia(),
                   Mat3::Identity() * vd * a * a * (95.0 + 39.0 * std::sqrt(5.0)) / 300.0, 1e-14);
  EXPECT_NEAR(dod.inradius(), a / 20.0 * std::sqrt(250.0 + 110.0 * std::sqrt(5.0)), 1e-14);
}

TEST(MassProperties, TriangularRidgePrism) {
  const double w = 0.5, h = 1.0, len = 4.0;  // BENCHMARKS.md C-EEp: ridge x in [-1.5, 2.5]
  const auto prism =
      ConvexPolyhedron::fromPoints(shapes::ridgePrism(Vec3(-1.5, 0, 0), Vec3(2.5, 0, 0), w, h));
  const double v = w * h * len;
  EXPECT_NEAR(prism.volume(), v, 1e-15 * v);
  EXPECT_LT((prism.centroid() - Vec3(0.5, 0, -2.0 * h / 3.0)).norm(), 1e-15);
  // Cross-section: isosceles triangle, base 2w, height h.
  const double iy_section = h * std::pow(2 * w, 3) / 48.0;  // int y^2 dA
  const double iz_section = 2 * w * h * h * h / 36.0;       // int z^2 dA about the centroid
  const double ix_length = w * h * len * len * len / 12.0;  // int x^2 dV
  expectMatrixNear(prism.inertia(),
                   diag(len * (iy_section + iz_section), ix_length + len * iz_section,
                        ix_length + len * iy_section),
                   1e-14);
  EXPECT_NEAR(prism.inradius(), w * h / (w + std::sqrt(h * h + w * w)), 1e-14);
}

TEST(MassProperties, SquarePyramidCentroidAtAQuarterOfTheHeight) {
  const double s = 1.0, h = 1.5;
  for (double turn : {0.0, degToRad(45.0), 0.3}) {
    const auto pyr = ConvexPolyhedron::fromPoints(
        shapes::squarePyramid(Vec3(0.2, -0.1, 0.0), s, h, shapes::Apex::kUp, turn));
    const double v = s * s * h / 3.0;
    EXPECT_NEAR(pyr.volume(), v, 1e-15 * v);
    // Base at z = -h, centroid h/4 above it.
    EXPECT_LT((pyr.centroid() - Vec3(0.2, -0.1, -h + h / 4.0)).norm(), 1e-15);
    const double ixy = v * (s * s / 20.0 + 3.0 * h * h / 80.0);
    expectMatrixNear(pyr.inertia(), diag(ixy, ixy, v * s * s / 10.0), 1e-14);
    EXPECT_NEAR(pyr.inradius(), s * h / (s + std::sqrt(4 * h * h + s * s)), 1e-14);
  }
  const auto down = ConvexPolyhedron::fromPoints(
      shapes::squarePyramid(Vec3(0, 0, -1e-5), 1.0, 1.0, shapes::Apex::kDown));
  EXPECT_NEAR(down.centroid().z(), -1e-5 + 0.75, 1e-15);
}

TEST(MassProperties, HexagonalPrism) {
  const double s = 0.25, len = 2.0;
  const auto rod = ConvexPolyhedron::fromPoints(shapes::hexagonalPrism(s, len));
  const double v = 1.5 * std::sqrt(3.0) * s * s * len;
  EXPECT_NEAR(rod.volume(), v, 1e-15 * v);
  const double ixy = v * (5.0 * s * s / 24.0 + len * len / 12.0);
  expectMatrixNear(rod.inertia(), diag(ixy, ixy, v * 5.0 * s * s / 12.0), 1e-14);
  EXPECT_NEAR(rod.inradius(), std::sqrt(3.0) / 2.0 * s, 1e-14);
  EXPECT_NEAR(rod.circumradius(), std::sqrt(s * s + len * len / 4.0), 1e-15);
}

TEST(MassProperties, IrregularPolyhedraAgreeWithAnIndependentDecomposition) {
  std::mt19937_64 rng(21);
  for (int n : {4, 7, 20, 100}) {
    for (std::uint64_t seed = 1; seed <= 5; ++seed) {
      const auto points = shapes::randomConvex(n, seed, Vec3(2.0, 1.0, 0.5), 0.4);
      const Vec3 shift(3.0, -1.0, 0.5);
      const auto p = ConvexPolyhedron::fromPoints(
          testing::transformedPoints(points, testing::randomRotation(rng), shift));
      const auto ref = testing::independentMassProperties(p);
      EXPECT_NEAR(p.volume(), ref.volume, 1e-13 * ref.volume);
      EXPECT_LT((p.centroid() - ref.centroid).norm(), 1e-13 * p.lengthScale());
      expectMatrixNear(p.inertia(), ref.inertia, 1e-12);
      // Volume as the sum of the pyramids from the centroid over each face.
      double pyramids = 0.0;
      for (const Face& f : p.faces()) {
        pyramids += f.area * (f.offset - f.normal.dot(p.centroid())) / 3.0;
      }
      EXPECT_NEAR(p.volume(), pyramids, 1e-13 * p.volume());
      // The inscribed sphere touches at least one face and stays inside all of them; the
      // circumscribed sphere holds every vertex and touches one.
      double nearest = std::numeric_limits<double>::infinity();
      for (const Face& f : p.faces())
        nearest = std::min(nearest, f.offset - f.normal.dot(p.incenter()));
      EXPECT_NEAR(nearest, p.inradius(), 1e-12 * p.lengthScale());
      EXPECT_GT(p.inradius(), 0.0);
      double farthest = 0.0;
      for (const Vec3& v : p.vertices()) farthest = std::max(farthest, (v - p.centroid()).norm());
      EXPECT_EQ(farthest, p.circumradius());
    }
  }
}

TEST(MassProperties, InscribedSphereIsTheLargest) {
  // Perturbing the centre of the inscribed sphere in any direction cannot fit a larger sphere.
  const auto p = ConvexPolyhedron::fromPoints(shapes::randomConvex(30, 4, Vec3(1.0, 0.7, 0.4)));
  const auto radiusAt = [&](const Vec3& x) {
    double r = std::numeric_limits<double>::infinity();
    for (const Face& f : p.faces()) r = std::min(r, f.offset - f.normal.dot(x));
    return r;
  };
  std::mt19937_64 rng(5);
  std::normal_distribution<double> normal;
  for (int i = 0; i < 200; ++i) {
    const Vec3 d = Vec3(normal(rng), normal(rng), normal(rng)).normalized() * 1e-3;
    EXPECT_LE(radiusAt(p.incenter() + d), p.inradius() + 1e-13);
  }
}

}  // namespace
}  // namespace polydem::geometry
