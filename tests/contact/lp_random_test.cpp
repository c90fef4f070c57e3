// The lp kernel on random polyhedron pairs (plates and rods among them) against independent
// references (brute-force separating axes for overlap, the Newton decrement computed afresh for
// the analytic centre, the line clipped by the face triangles for the depth), on separated,
// touching, deep and degenerate pairs, and with warm starts along a trajectory (same answers as
// cold, no allocation).
#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <memory>
#include <random>

#include "common/allocation_counter.h"
#include "contact/lp_test_util.h"
#include "polydem/contact/contact_cases.h"
#include "polydem/contact/potential/lp.h"
#include "polydem/geometry/shapes.h"

namespace polydem::contact {
namespace {

using testing::Placed;
using testing::randomRotation;
using testing::randomUnit;
using testing::worldPlanes;

// Smallest overlap of the projections of the two vertex sets over A's and B's face normals and
// the cross products of their edges: the penetration depth if positive, minus a gap if negative.
double satOverlap(const Body& a, const Body& b) {
  auto project = [](const Body& body, const Vec3& u, double& lo, double& hi) {
    lo = std::numeric_limits<double>::infinity();
    hi = -lo;
    for (const Vec3& v : body.vertices) {
      lo = std::min(lo, u.dot(v));
      hi = std::max(hi, u.dot(v));
    }
  };
  double best = std::numeric_limits<double>::infinity();
  auto test = [&](const Vec3& axis) {
    const double length = axis.norm();
    if (length == 0.0) return;
    const Vec3 u = axis / length;
    double la, ha, lb, hb;
    project(a, u, la, ha);
    project(b, u, lb, hb);
    best = std::min(best, std::min(ha - lb, hb - la));
  };
  for (const Body* body : {&a, &b}) {
    for (const auto& f : body->shape->faces()) test(body->rotation * f.normal);
  }
  for (const auto& ea : a.shape->edges()) {
    const Vec3 da = a.vertices[ea.v1] - a.vertices[ea.v0];
    for (const auto& eb : b.shape->edges()) {
      const Vec3 db = b.vertices[eb.v1] - b.vertices[eb.v0];
      const Vec3 axis = da.cross(db);
      if (axis.norm() > 1e-9 * da.norm() * db.norm()) test(axis);
    }
  }
  return best;
}

// The interval of t for which x0 + t u is inside `body`, from the crossings of the line with the
// triangles of its faces (Moller-Trumbore): built from the vertices, not from the face planes.
std::pair<double, double> clipByTriangles(const Body& body, const Vec3& x0, const Vec3& u) {
  double t_minus = -std::numeric_limits<double>::infinity();
  double t_plus = std::numeric_limits<double>::infinity();
  for (const auto& f : body.shape->faces()) {
    const Vec3& v0 = body.vertices[f.vertices[0]];
    for (std::size_t k = 1; k + 1 < f.vertices.size(); ++k) {
      const Vec3 e1 = body.vertices[f.vertices[k]] - v0;
      const Vec3 e2 = body.vertices[f.vertices[k + 1]] - v0;
      const Vec3 p = u.cross(e2);
      const double det = e1.dot(p);
      if (std::abs(det) < 1e-14 * e1.norm() * e2.norm()) continue;  // line in the face's plane
      const Vec3 s = x0 - v0;
      const double beta = s.dot(p) / det;
      const Vec3 q = s.cross(e1);
      const double gamma = u.dot(q) / det;
      const double t = e2.dot(q) / det;
      constexpr double kEdge = 1e-10;
      if (beta < -kEdge || gamma < -kEdge || beta + gamma > 1.0 + kEdge) continue;
      if (t > 0.0) t_plus = std::min(t_plus, t);
      if (t < 0.0) t_minus = std::max(t_minus, t);
    }
  }
  return {t_minus, t_plus};
}

double clippedDepth(const Body& a, const Body& b, const Contact& c) {
  const auto [a0, a1] = clipByTriangles(a, c.point, c.normal);
  const auto [b0, b1] = clipByTriangles(b, c.point, c.normal);
  return std::min(a1, b1) - std::max(a0, b0);
}

// min over both bodies' faces of d - n . x (positive: strictly inside both).
double minSlack(const Body& a, const Body& b, const Vec3& x) {
  double smallest = std::numeric_limits<double>::infinity();
  for (const Body* body : {&a, &b}) {
    for (const auto& p : worldPlanes(*body))
      smallest = std::min(smallest, p.offset - p.normal.dot(x));
  }
  return smallest;
}

// The Newton decrement of -sum log(d - n . x) over both bodies' faces, computed afresh.
double newtonDecrement(const Body& a, const Body& b, const Vec3& x) {
  Vec3 g = Vec3::Zero();
  Mat3 h = Mat3::Zero();
  for (const Body* body : {&a, &b}) {
    for (const auto& p : worldPlanes(*body)) {
      const Vec3 u = p.normal / (p.offset - p.normal.dot(x));
      g += u;
      h += u * u.transpose();
    }
  }
  return std::sqrt(std::max(0.0, g.dot(h.ldlt().solve(g))));
}

// 8-40 vertices on a perturbed ellipsoid; `thin`: a plate (one semi-axis 1e-3..1e-2 of the
// others) or a rod (two).
std::vector<Vec3> randomShape(std::mt19937_64& rng, std::uint64_t seed, bool thin = false) {
  std::uniform_real_distribution<double> axis(0.3, 1.0), flat(1e-3, 1e-2);
  std::uniform_int_distribution<int> count(8, 40);
  Vec3 axes(axis(rng), axis(rng), axis(rng));
  if (thin) {
    axes[seed % 3] *= flat(rng);
    if (seed % 2 == 0) axes[(seed + 1) % 3] *= flat(rng);
  }
  return geometry::shapes::randomConvex(count(rng), seed, axes, 0.2);
}

TEST(LpKernelRandom, OverlapPointAndDepthAgainstIndependentReferences) {
  const LpKernel kernel;
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  int overlapping = 0, apart = 0;
  double shortest = std::numeric_limits<double>::infinity(), longest = 0.0;
  for (int n = 0; n < 400; ++n) {
    // A quarter of the pairs involve a plate or a rod.
    const Placed a(randomShape(rng, 100 + n, n % 8 == 1), randomRotation(rng), Vec3::Zero());
    const std::vector<Vec3> b_points = randomShape(rng, 700 + n, n % 8 == 5);
    const double reach = 0.8 * (a.shape.circumradius() + 1.0);
    const Placed b(b_points, randomRotation(rng), randomUnit(rng) * reach * unit(rng));
    const double size = a.body.circumradius() + b.body.circumradius();
    const double sat = satOverlap(a.body, b.body);
    if (std::abs(sat) < 1e-9 * size) continue;  // too close to touching to call
    const Contact c = kernel.collide(a.body, b.body, nullptr);
    ASSERT_EQ(c.touching, sat > 0.0) << n << " SAT overlap " << sat;
    if (!c.touching) {
      ++apart;
      continue;
    }
    ++overlapping;
    EXPECT_NE(c.status, Status::kNotConverged) << n;
    EXPECT_NEAR(c.normal.norm(), 1.0, 1e-14) << n;
    EXPECT_GT(minSlack(a.body, b.body, c.point), 0.0) << n;
    EXPECT_LE(newtonDecrement(a.body, b.body, c.point), 1e-6) << n;
    EXPECT_NEAR(c.depth, clippedDepth(a.body, b.body, c), 1e-9 * size) << n;
    // The chord through the centre along n is not the minimum translation that separates the
    // pair (the SAT overlap): recorded.
    shortest = std::min(shortest, c.depth / sat);
    longest = std::max(longest, c.depth / sat);
  }
  EXPECT_GT(overlapping, 100);
  EXPECT_GT(apart, 100);
  std::printf("%d overlapping, %d apart; chord depth / SAT penetration depth in [%.3g, %.3g]\n",
              overlapping, apart, shortest, longest);
}

TEST(LpKernelRandom, SeparatedAndTouchingPairs) {
  const LpKernel kernel;
  const std::vector<Vec3> cube = geometry::shapes::cube(1.0);
  const Placed b(cube);
  // Bounding spheres apart.
  const Placed far(cube, Mat3::Identity(), Vec3(3.0, 0.0, 0.0));
  EXPECT_FALSE(kernel.collide(far.body, b.body, nullptr).touching);
  EXPECT_TRUE(LpKernel::lastTrace().spheres_apart);
  // Faces 1e-9 apart, exactly touching, 1e-9 into each other.
  for (const double gap : {1e-9, 0.0, -1e-9}) {
    const Placed a(cube, Mat3::Identity(), Vec3(0.3, -0.2, 1.0 + gap));
    const Contact c = kernel.collide(a.body, b.body, nullptr);
    EXPECT_EQ(c.touching, gap < 0.0) << gap;
    if (c.touching) {
      EXPECT_NEAR(c.depth, -gap, 1e-6 * -gap);
      EXPECT_LE(angleBetween(c.normal, Vec3::UnitZ()), 1e-9);
    }
  }
  // Corner on corner along the diagonal, and edge across edge, exactly touching.
  const Placed corner(cube, Mat3::Identity(), Vec3(1.0, 1.0, 1.0));
  EXPECT_FALSE(kernel.collide(corner.body, b.body, nullptr).touching);
  const Mat3 turn = Eigen::AngleAxisd(0.25 * kPi, Vec3::UnitZ()).matrix() *
                    Eigen::AngleAxisd(0.25 * kPi, Vec3::UnitX()).matrix();
  const Placed edge(cube, turn, Vec3(0.0, 0.0, 0.5 + std::sqrt(0.5)));
  const Contact e = kernel.collide(edge.body, b.body, nullptr);
  EXPECT_FALSE(e.touching);
}

TEST(LpKernelRandom, SeparatedPairsRememberASeparatingDirection) {
  const LpKernel kernel;
  const std::vector<Vec3> cube = geometry::shapes::cube(1.0);
  const Placed b(cube);
  // Apart along x by 1e-6, but the line of centres (1, 0.9, 0) does not separate them: the LP
  // decides, and its dual's direction is kept; the next call needs only that direction.
  const Placed a(cube, Mat3::Identity(), Vec3(1.0 + 1e-6, 0.9, 0.0));
  particles::PairState state;
  EXPECT_FALSE(kernel.collide(a.body, b.body, &state).touching);
  EXPECT_TRUE(LpKernel::lastTrace().lp_solved);
  EXPECT_FALSE(LpKernel::lastTrace().centre_line_apart);
  EXPECT_NEAR(LpKernel::lastTrace().lp_objective, 0.5e-6, 1e-12);  // half the gap
  EXPECT_FALSE(kernel.collide(a.body, b.body, &state).touching);
  EXPECT_TRUE(LpKernel::lastTrace().warm_axis);
  EXPECT_FALSE(LpKernel::lastTrace().lp_solved);
  // Moved into contact: the direction no longer separates, the LP (from its last basis) and
  // Newton take over, and the answer is the cold one.
  const Placed in(cube, Mat3::Identity(), Vec3(1.0 - 1e-6, 0.9, 0.0));
  const Contact warm = kernel.collide(in.body, b.body, &state);
  EXPECT_TRUE(LpKernel::lastTrace().lp_warm_basis || LpKernel::lastTrace().centre_line);
  const Contact cold = kernel.collide(in.body, b.body, nullptr);
  ASSERT_TRUE(warm.touching && cold.touching);
  EXPECT_LE(angleBetween(warm.normal, cold.normal), 1e-12);
  EXPECT_LE(angleBetween(warm.normal, Vec3::UnitX()), 1e-12);
  EXPECT_NEAR(warm.depth, 1e-6, 1e-12);
  // Face to face 1e-9 apart along the line of centres: that line separates them, no LP.
  const Placed above(cube, Mat3::Identity(), Vec3(0.0, 0.0, 1.0 + 1e-9));
  particles::PairState fresh;
  EXPECT_FALSE(kernel.collide(above.body, b.body, &fresh).touching);
  EXPECT_TRUE(LpKernel::lastTrace().centre_line_apart);
  EXPECT_FALSE(LpKernel::lastTrace().lp_solved);
  EXPECT_FALSE(kernel.collide(above.body, b.body, &fresh).touching);
  EXPECT_TRUE(LpKernel::lastTrace().warm_axis);
}

TEST(LpKernelRandom, DeepAndDegenerateOverlaps) {
  const LpKernel kernel;
  const std::vector<Vec3> cube = geometry::shapes::cube(1.0);
  const Placed b(cube);
  // Sunk 0.3 deep (deeper than 2r: the potentials' gradients vanish at the point and their
  // limit, the nearest face's normal, is used): vertical, depth 0.3.
  const Placed sunk(cube, Mat3::Identity(), Vec3(0.0, 0.0, 0.7));
  Contact c = kernel.collide(sunk.body, b.body, nullptr);
  ASSERT_TRUE(c.touching);
  EXPECT_EQ(c.status, Status::kOk);
  EXPECT_LE(angleBetween(c.normal, Vec3::UnitZ()), 1e-12);
  EXPECT_NEAR(c.depth, 0.3, 1e-12);
  EXPECT_LE((c.point - Vec3(0.0, 0.0, 0.35)).norm(), 1e-12);
  // Identical bodies: every direction is as good; the kernel says so and still gives a chord.
  const Placed same(cube);
  c = kernel.collide(same.body, b.body, nullptr);
  ASSERT_TRUE(c.touching);
  EXPECT_EQ(c.status, Status::kDegenerate);
  EXPECT_LE(c.point.norm(), 1e-12);
  EXPECT_NEAR(c.depth, clippedDepth(same.body, b.body, c), 1e-12);
  // One inside the other, off-centre, both ways round.
  std::mt19937_64 rng(5);
  const Placed small(geometry::shapes::cube(0.2), randomRotation(rng), Vec3(0.2, -0.1, 0.15));
  for (const bool small_first : {true, false}) {
    const Body& first = small_first ? small.body : b.body;
    const Body& second = small_first ? b.body : small.body;
    c = kernel.collide(first, second, nullptr);
    ASSERT_TRUE(c.touching);
    EXPECT_GT(minSlack(first, second, c.point), 0.0);
    EXPECT_LE(newtonDecrement(first, second, c.point), 1e-6);
    EXPECT_NEAR(c.depth, clippedDepth(first, second, c), 1e-12);
    EXPECT_NEAR(c.normal.norm(), 1.0, 1e-14);
  }
}

// A slides across B, tilting, sinks in and lifts off: with the pair's state (warm point, LP basis,
// separating direction) the kernel gives the cold answer at every step.
TEST(LpKernelRandom, WarmStartsGiveTheColdAnswer) {
  const LpKernel kernel;
  std::mt19937_64 rng(12);
  const Placed b(randomShape(rng, 42), randomRotation(rng), Vec3::Zero());
  const std::vector<Vec3> a_points = randomShape(rng, 43);
  const Mat3 a_rotation = randomRotation(rng);
  const Vec3 axis = randomUnit(rng), direction = randomUnit(rng);
  const double reach =
      geometry::ConvexPolyhedron::fromPoints(a_points).circumradius() + b.shape.circumradius();
  particles::PairState state;
  int touching = 0, warm_points = 0, warm_axes = 0;
  for (int step = 0; step <= 400; ++step) {
    // The centres from 1.05 reach down to 0.25 reach and back (centroids near the origins).
    const double s = std::abs(step - 200) / 200.0;
    const Vec3 position =
        direction * reach * (0.25 + 0.8 * s) + 1e-3 * step * axis.cross(direction);
    const Mat3 rotation = Eigen::AngleAxisd(1e-3 * step, axis).matrix() * a_rotation;
    const Placed a(a_points, rotation, position);
    const Contact cold = kernel.collide(a.body, b.body, nullptr);
    const Contact warm = kernel.collide(a.body, b.body, &state);
    warm_points += LpKernel::lastTrace().warm_point;
    warm_axes += LpKernel::lastTrace().warm_axis;
    ASSERT_EQ(warm.touching, cold.touching) << step;
    if (!cold.touching) continue;
    ++touching;
    const double size = a.body.circumradius() + b.body.circumradius();
    EXPECT_LE(angleBetween(warm.normal, cold.normal), 1e-8) << step;
    EXPECT_LE((warm.point - cold.point).norm(), 1e-9 * size) << step;
    EXPECT_NEAR(warm.depth, cold.depth, 1e-9 * size) << step;
  }
  EXPECT_GT(touching, 100);
  EXPECT_GT(warm_points, touching * 8 / 10);  // the last point is reused nearly every time
  EXPECT_GT(warm_axes, 10);
  std::printf(
      "trajectory: %d of 401 steps touching, %d started from the last point, %d apart "
      "by the last separating direction\n",
      touching, warm_points, warm_axes);
}

TEST(LpKernelRandom, DeterministicAndAllocationFreeOnceWarm) {
  const LpKernel kernel;
  std::mt19937_64 rng(13);
  std::vector<std::unique_ptr<Placed>> bodies;
  for (int n = 0; n < 12; ++n) {
    bodies.push_back(std::make_unique<Placed>(randomShape(rng, 300 + n), randomRotation(rng),
                                              0.6 * randomUnit(rng)));
  }
  std::vector<particles::PairState> states(bodies.size() * bodies.size());
  auto sweep = [&]() {
    for (std::size_t i = 0; i < bodies.size(); ++i) {
      for (std::size_t j = i + 1; j < bodies.size(); ++j) {
        particles::PairState& st = states[i * bodies.size() + j];
        particles::PairState copy = st;
        const Contact first = kernel.collide(bodies[i]->body, bodies[j]->body, &st);
        const Contact second = kernel.collide(bodies[i]->body, bodies[j]->body, &copy);
        ASSERT_EQ(std::memcmp(&st, &copy, sizeof(particles::PairState)), 0);
        EXPECT_EQ(first.touching, second.touching);
        EXPECT_EQ(first.normal, second.normal);
        EXPECT_EQ(first.point, second.point);
        EXPECT_EQ(first.depth, second.depth);
        kernel.collide(bodies[i]->body, bodies[j]->body, nullptr);
      }
    }
  };
  sweep();  // grows the per-thread buffers to the largest pair
  const long before = polydem::testing::allocationCount();
  sweep();
  EXPECT_EQ(polydem::testing::allocationCount(), before);
}

}  // namespace
}  // namespace polydem::contact
