// The analytic centre by Newton's method against sets whose centre is known in closed form:
// a box (its centre), a tetrahedron (its vertex centroid: the centre is affine invariant and the
// regular simplex's is its centroid), thin and rotated versions of both (the QR fallback), and
// the chord of a line through a set against the vertices it must pass.
#include "polydem/geometry/analytic_centre.h"

#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <cmath>
#include <limits>
#include <random>

#include "polydem/geometry/convex_polyhedron.h"
#include "polydem/geometry/halfspaces.h"

namespace polydem::geometry {
namespace {

using LineSearch = AnalyticCentreOptions::LineSearch;

Mat3 randomRotation(std::mt19937_64& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  return Quat(n(rng), n(rng), n(rng), n(rng)).normalized().toRotationMatrix();
}

// The faces of the hull of `points`, moved by x -> R x + t.
Halfspaces facesOf(const std::vector<Vec3>& points, const Mat3& r = Mat3::Identity(),
                   const Vec3& t = Vec3::Zero()) {
  const ConvexPolyhedron p = ConvexPolyhedron::fromPoints(points);
  Halfspaces h;
  for (const Face& f : p.faces()) {
    const Vec3 a = r * f.normal;
    h.add(a, f.offset + a.dot(t));
  }
  return h;
}

// The six planes of the box |x_k| <= half_k moved by x -> R x + t (built directly: a box too
// thin for a hull).
Halfspaces boxFaces(const Vec3& half, const Mat3& r = Mat3::Identity(),
                    const Vec3& t = Vec3::Zero()) {
  Halfspaces h;
  for (int k = 0; k < 3; ++k) {
    for (double sign : {1.0, -1.0}) {
      const Vec3 a = sign * r.col(k);
      h.add(a, half[k] + a.dot(t));
    }
  }
  return h;
}

std::vector<Vec3> boxCorners(const Vec3& half) {
  std::vector<Vec3> v;
  for (int i = 0; i < 8; ++i) {
    v.emplace_back((i & 1) ? half.x() : -half.x(), (i & 2) ? half.y() : -half.y(),
                   (i & 4) ? half.z() : -half.z());
  }
  return v;
}

// Newton decrement at x computed independently (Eigen's LDLT on the Hessian).
double decrementAt(const Halfspaces& h, const Vec3& x) {
  Vec3 g = Vec3::Zero();
  Mat3 hess = Mat3::Zero();
  for (int i = 0; i < h.size(); ++i) {
    const Vec3 u = h.normal(i) / h.slack(i, x);
    g += u;
    hess += u * u.transpose();
  }
  return std::sqrt(std::max(0.0, g.dot(hess.ldlt().solve(g))));
}

TEST(AnalyticCentre, BoxCentreFromAnyInteriorStart) {
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> u(-0.999, 0.999);
  for (int n = 0; n < 200; ++n) {
    const Vec3 half(0.5, 0.2 + 0.1 * (n % 5), 3.0);
    const Mat3 r = randomRotation(rng);
    const Vec3 t(u(rng), u(rng), u(rng));
    const Halfspaces h = boxFaces(half, r, t);
    const Vec3 start = t + r * half.cwiseProduct(Vec3(u(rng), u(rng), u(rng)));
    for (const LineSearch ls : {LineSearch::kExact, LineSearch::kBacktracking}) {
      AnalyticCentreOptions o;
      o.line_search = ls;
      const AnalyticCentreResult c = analyticCentre(h, start, o);
      ASSERT_TRUE(c.converged) << n;
      EXPECT_LE((c.x - t).norm(), 1e-12 * half.norm()) << n;
      EXPECT_LE(decrementAt(h, c.x), 1e-9) << n;
      EXPECT_LE(c.decrement, 1e-6);
    }
  }
}

TEST(AnalyticCentre, TetrahedronCentreIsVertexCentroid) {
  std::mt19937_64 rng(2);
  std::normal_distribution<double> n01(0.0, 1.0);
  for (int n = 0; n < 200; ++n) {
    std::vector<Vec3> v(4);
    for (Vec3& p : v) p = Vec3(n01(rng), n01(rng), n01(rng));
    const Vec3 centroid = 0.25 * (v[0] + v[1] + v[2] + v[3]);
    const double volume = std::abs((v[1] - v[0]).cross(v[2] - v[0]).dot(v[3] - v[0])) / 6.0;
    if (volume < 1e-2) continue;  // keep the hull well defined
    const Halfspaces h = facesOf(v);
    // Start near a vertex: the damped phase of Newton's method has work to do.
    const Vec3 start = 0.98 * v[n % 4] + 0.02 * centroid;
    const AnalyticCentreResult c = analyticCentre(h, start);
    ASSERT_TRUE(c.converged) << n;
    double extent = 0.0;
    for (const Vec3& p : v) extent = std::max(extent, (p - centroid).norm());
    EXPECT_LE((c.x - centroid).norm(), 1e-11 * extent) << n;
  }
}

TEST(AnalyticCentre, ThinRotatedBoxesAndScales) {
  // Width 2e-10 across, 2 along: H's condition number reaches 1e20 and the Cholesky factor fails;
  // the step then comes from the QR factorisation of J. The slacks across are known only to
  // about eps * extent / width of themselves (the offsets are of the extent's size), which bounds
  // how well the centre is determined, in every direction: the test asks for 10 times that.
  std::mt19937_64 rng(3);
  constexpr double kEps = std::numeric_limits<double>::epsilon();
  for (double thin : {1e-3, 1e-6, 1e-8, 1e-10}) {
    const double tol = std::max(1e-12, 10.0 * kEps / thin);
    for (double scale : {1e-3, 1.0, 1e3}) {
      const Mat3 r = randomRotation(rng);
      const Vec3 t = scale * Vec3(0.3, -0.7, 2.0);
      const Vec3 half = scale * Vec3(1.0, 0.6, thin);
      const Halfspaces h = boxFaces(half, r, t);
      const Vec3 start = t + r * Vec3(0.9 * half.x(), -0.8 * half.y(), 0.5 * half.z());
      for (const LineSearch ls : {LineSearch::kExact, LineSearch::kBacktracking}) {
        AnalyticCentreOptions o;
        o.line_search = ls;
        const AnalyticCentreResult c = analyticCentre(h, start, o);
        EXPECT_TRUE(c.converged) << thin << " " << scale;
        const Vec3 local = r.transpose() * (c.x - t);
        EXPECT_LE(std::abs(local.x()), tol * half.x()) << thin << " " << scale;
        EXPECT_LE(std::abs(local.y()), tol * half.y()) << thin << " " << scale;
        EXPECT_LE(std::abs(local.z()), tol * half.z()) << thin << " " << scale;
      }
    }
  }
}

TEST(AnalyticCentre, StartMarginAndIterationBound) {
  const Halfspaces h = facesOf(boxCorners(Vec3(1.0, 1.0, 1.0)));
  AnalyticCentreOptions o;
  o.start_margin = 0.1;
  AnalyticCentreResult c = analyticCentre(h, Vec3(0.95, 0.0, 0.0), o);  // slack 0.05 < 0.1
  EXPECT_TRUE(c.start_rejected);
  EXPECT_EQ(c.iterations, 0);
  EXPECT_EQ(c.x, Vec3(0.95, 0.0, 0.0));
  c = analyticCentre(h, Vec3(2.0, 0.0, 0.0));  // outside
  EXPECT_TRUE(c.start_rejected);
  c = analyticCentre(h, Vec3(0.85, 0.0, 0.0), o);
  EXPECT_FALSE(c.start_rejected);
  EXPECT_TRUE(c.converged);
  o.start_margin = 0.0;
  o.max_iterations = 1;
  c = analyticCentre(h, Vec3(0.999999, 0.999, -0.9999), o);
  EXPECT_FALSE(c.converged);
  EXPECT_EQ(c.iterations, 1);
  EXPECT_GT(h.minSlack(c.x), 0.0);
}

TEST(AnalyticCentre, UnboundedSetIsNotConverged) {
  // A slab: the Hessian is singular along the slab.
  Halfspaces h;
  h.add(Vec3(0, 0, 1), 1.0);
  h.add(Vec3(0, 0, -1), 1.0);
  const AnalyticCentreResult c = analyticCentre(h, Vec3(0.2, 0.3, 0.5));
  EXPECT_FALSE(c.converged);
  EXPECT_FALSE(c.start_rejected);
}

TEST(AnalyticCentre, BarrierGradientVanishesAtTheCentre) {
  const Halfspaces h = facesOf({{0, 0, 0}, {2, 0, 0}, {0, 3, 0}, {0, 0, 1}, {1, 1, 1}});
  const AnalyticCentreResult c = analyticCentre(h, Vec3(0.3, 0.3, 0.1));
  ASSERT_TRUE(c.converged);
  double scale = 0.0;
  for (int i = 0; i < h.size(); ++i) scale += 1.0 / h.slack(i, c.x);
  EXPECT_LE(barrierGradient(h, c.x).norm(), 1e-12 * scale);
}

TEST(Halfspaces, ChordThroughABox) {
  const Halfspaces h = facesOf(boxCorners(Vec3(1.0, 2.0, 3.0)));
  Halfspaces::Chord c = h.chord(Vec3(0.5, 0.0, 0.0), Vec3(2.0, 0.0, 0.0));
  EXPECT_DOUBLE_EQ(c.t_min, -0.75);
  EXPECT_DOUBLE_EQ(c.t_max, 0.25);
  EXPECT_DOUBLE_EQ(c.length(), 1.0);
  // Diagonal: the line leaves through the nearest of the planes it crosses.
  c = h.chord(Vec3::Zero(), Vec3(1.0, 1.0, 1.0));
  EXPECT_DOUBLE_EQ(c.t_max, 1.0);
  EXPECT_DOUBLE_EQ(c.t_min, -1.0);
  // Parallel to two faces and outside them: empty.
  c = h.chord(Vec3(5.0, 0.0, 0.0), Vec3(0.0, 0.0, 1.0));
  EXPECT_GT(c.t_min, c.t_max);
  EXPECT_EQ(c.length(), 0.0);
  EXPECT_DOUBLE_EQ(h.minSlack(Vec3(0.5, 1.0, -2.0)), 0.5);
  EXPECT_DOUBLE_EQ(h.minSlack(Vec3(0.5, 1.0, -2.0), 0, 0), std::numeric_limits<double>::infinity());
}

}  // namespace
}  // namespace polydem::geometry
