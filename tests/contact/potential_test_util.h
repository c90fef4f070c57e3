// Helpers shared by the potential-kernel tests (distance-potential, fdem): placed bodies, random
// rotations, and the independent reference of Zhao eq. (3): the overlap polyhedron built by
// clipping A by B's face planes (ConvexPolyhedron::split), its boundary integral of
// n (phi_A - phi_B) dS and its moment by brute-force quadrature (every face fanned into triangles,
// each cut into n^2 sub-triangles, centroid rule).
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <functional>
#include <memory>
#include <optional>
#include <random>
#include <vector>

#include "polydem/contact/contact.h"
#include "polydem/contact/contact_cases.h"
#include "polydem/core/error.h"
#include "polydem/geometry/convex_polyhedron.h"
#include "polydem/geometry/shapes.h"

namespace polydem::contact::testing {

/// A shape with its own vertex storage, placed in the world.
struct Placed {
  std::unique_ptr<geometry::ConvexPolyhedron> shape;
  std::vector<Vec3> storage;
  Body body;
};

/// The shape built from `points` (in its own frame), placed at (position, rotation).
inline Placed place(const std::vector<Vec3>& points, const Vec3& position = Vec3::Zero(),
                    const Mat3& rotation = Mat3::Identity()) {
  Placed p;
  p.shape =
      std::make_unique<geometry::ConvexPolyhedron>(geometry::ConvexPolyhedron::fromPoints(points));
  p.body = placeBody(*p.shape, position, rotation, p.storage);
  return p;
}

/// The world polyhedron of a placed body.
inline geometry::ConvexPolyhedron worldShape(const Body& b) {
  return geometry::ConvexPolyhedron::fromPoints(
      std::vector<Vec3>(b.vertices.begin(), b.vertices.end()));
}

inline Mat3 randomRotation(std::mt19937_64& rng) {
  std::normal_distribution<double> g;
  Eigen::Quaterniond q(g(rng), g(rng), g(rng), g(rng));
  return q.normalized().toRotationMatrix();
}

inline Mat3 rotationAbout(const Vec3& axis, double angle) {
  return Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix();
}

/// `a` clipped by every face plane of `b` (their overlap), or nothing when they do not overlap.
inline std::optional<geometry::ConvexPolyhedron> overlapPolyhedron(
    const geometry::ConvexPolyhedron& a, const geometry::ConvexPolyhedron& b) {
  geometry::ConvexPolyhedron v = a;
  for (const auto& f : b.faces()) {
    const auto parts = v.split(geometry::Plane{f.normal, f.offset});
    if (parts.below.size() < 4) return std::nullopt;
    if (parts.above.empty()) continue;
    try {
      v = geometry::ConvexPolyhedron::fromPoints(parts.below);
    } catch (const Error&) {
      return std::nullopt;  // a sliver flat at round-off: no overlap to speak of
    }
  }
  return v;
}

/// The distance along `dir` from B's centroid at which A's centroid puts A just in touch with B
/// (bisection on the existence of the overlap polyhedron).
inline double touchingDistance(const std::vector<Vec3>& a_points, const Mat3& a_rotation,
                               const geometry::ConvexPolyhedron& b_world, const Vec3& dir) {
  const auto a0 =
      geometry::ConvexPolyhedron::fromPoints(a_points).transformed(a_rotation, Vec3::Zero());
  double lo = 0.0, hi = a0.circumradius() + b_world.circumradius() + (a0.centroid()).norm() + 1.0;
  for (int k = 0; k < 50; ++k) {
    const double mid = 0.5 * (lo + hi);
    const auto a = a0.transformed(Mat3::Identity(), b_world.centroid() + mid * dir - a0.centroid());
    (overlapPolyhedron(a, b_world).has_value() ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

struct BoundaryIntegral {
  Vec3 force = Vec3::Zero();   // integral of n (phi_A - phi_B) dS
  Vec3 moment = Vec3::Zero();  // integral of x cross n (phi_A - phi_B) dS about the world origin
};

using Potential = std::function<double(const Vec3&)>;

/// Brute-force quadrature of Zhao eq. (3) over the boundary of `v`.
inline BoundaryIntegral quadrature(const geometry::ConvexPolyhedron& v, const Potential& phi_a,
                                   const Potential& phi_b, int n) {
  BoundaryIntegral out;
  const auto& xs = v.vertices();
  for (const auto& face : v.faces()) {
    for (std::size_t k = 1; k + 1 < face.vertices.size(); ++k) {
      const Vec3 p0 = xs[face.vertices[0]], e1 = xs[face.vertices[k]] - p0,
                 e2 = xs[face.vertices[k + 1]] - p0;
      const double sub_area = 0.5 * e1.cross(e2).norm() / (n * n);
      for (int i = 0; i < n; ++i) {
        for (int j = 0; i + j < n; ++j) {
          // Upright sub-triangle (i, j), and the inverted one beside it where there is one.
          for (int flip = 0; flip < 2; ++flip) {
            if (flip == 1 && i + j + 1 >= n) continue;
            const double s = flip == 0 ? (i + 1.0 / 3.0) / n : (i + 2.0 / 3.0) / n;
            const double t = flip == 0 ? (j + 1.0 / 3.0) / n : (j + 2.0 / 3.0) / n;
            const Vec3 x = p0 + s * e1 + t * e2;
            const Vec3 df = sub_area * (phi_a(x) - phi_b(x)) * face.normal;
            out.force += df;
            out.moment += x.cross(df);
          }
        }
      }
    }
  }
  return out;
}

/// Distance potential from the definition: (distance to the nearest point of the surface) / r,
/// the surface taken face polygon by face polygon (no use of the min-over-planes formula).
inline double distanceToSurface(const geometry::ConvexPolyhedron& p, const Vec3& x) {
  double best = std::numeric_limits<double>::infinity();
  const auto& xs = p.vertices();
  for (const auto& f : p.faces()) {
    const double d = f.normal.dot(x) - f.offset;
    const Vec3 foot = x - d * f.normal;
    bool inside = true;
    const std::size_t m = f.vertices.size();
    for (std::size_t i = 0; i < m; ++i) {
      const Vec3& a = xs[f.vertices[i]];
      const Vec3& b = xs[f.vertices[(i + 1) % m]];
      if ((b - a).cross(foot - a).dot(f.normal) < 0.0) inside = false;
    }
    if (inside) {
      best = std::min(best, std::abs(d));
      continue;
    }
    for (std::size_t i = 0; i < m; ++i) {
      const Vec3& a = xs[f.vertices[i]];
      const Vec3& b = xs[f.vertices[(i + 1) % m]];
      const double t = std::clamp((x - a).dot(b - a) / (b - a).squaredNorm(), 0.0, 1.0);
      best = std::min(best, (x - (a + t * (b - a))).norm());
    }
  }
  return best;
}

/// min over face planes of the inward distance, clamped at 0 outside.
inline double planeClearance(const geometry::ConvexPolyhedron& p, const Vec3& x) {
  double d = std::numeric_limits<double>::infinity();
  for (const auto& f : p.faces()) d = std::min(d, f.offset - f.normal.dot(x));
  return std::max(d, 0.0);
}

/// Tetrahedra of the FDEM split of a world polyhedron: itself if it is a tetrahedron, else one per
/// face triangle from the centroid, polygonal faces fanned from their centroid.
inline std::vector<std::array<Vec3, 4>> fdemTetrahedra(const geometry::ConvexPolyhedron& p) {
  std::vector<std::array<Vec3, 4>> out;
  const auto& xs = p.vertices();
  if (xs.size() == 4) return {{xs[0], xs[1], xs[2], xs[3]}};
  for (const auto& f : p.faces()) {
    const std::size_t m = f.vertices.size();
    if (m == 3) {
      out.push_back({p.centroid(), xs[f.vertices[0]], xs[f.vertices[1]], xs[f.vertices[2]]});
      continue;
    }
    for (std::size_t i = 0; i < m; ++i) {
      out.push_back({p.centroid(), f.centroid, xs[f.vertices[i]], xs[f.vertices[(i + 1) % m]]});
    }
  }
  return out;
}

/// Munjiza's potential from its definition: in the tetrahedron containing x, min_i 4 V_i(x) / V,
/// which is 4 times x's smallest barycentric coordinate; 0 outside every tetrahedron.
class FdemPotential {
 public:
  explicit FdemPotential(const std::vector<std::array<Vec3, 4>>& tets) {
    for (const auto& t : tets) {
      Mat3 m;
      m << t[1] - t[0], t[2] - t[0], t[3] - t[0];
      Vec3 c = 0.25 * (t[0] + t[1] + t[2] + t[3]);
      double radius = 0.0;
      for (const Vec3& p : t) radius = std::max(radius, (p - c).norm());
      maps_.push_back({t[0], m.inverse(), c, radius * (1 + 1e-9)});
    }
  }
  double operator()(const Vec3& x) const {
    for (const auto& m : maps_) {
      if ((x - m.centre).norm() > m.radius) continue;
      const Vec3 l = m.inverse * (x - m.origin);
      const double lmin = std::min({1.0 - l.sum(), l.x(), l.y(), l.z()});
      if (lmin >= -1e-12) return 4.0 * std::max(lmin, 0.0);
    }
    return 0.0;
  }

 private:
  struct Map {
    Vec3 origin;
    Mat3 inverse;
    Vec3 centre;
    double radius;
  };
  std::vector<Map> maps_;
};

struct Pressed {
  double potential;
  Vec3 normal;
};

// A box with an a x a foot and the given height pressed by `delta` onto face f of `t`, its foot
// centred on the face's point of tangency with the inscribed sphere.
inline Pressed pressBoxOnFace(const Kernel& kernel, const Placed& t, int f, double a, double height,
                              double delta, double* room = nullptr) {
  const auto& face = t.shape->faces()[f];
  const Vec3 n = face.normal;
  const Vec3 tangent = t.shape->incenter() + (face.offset - n.dot(t.shape->incenter())) * n;
  if (room) {  // distance from the tangency point to the face's edges
    *room = std::numeric_limits<double>::infinity();
    const auto& xs = t.shape->vertices();
    for (std::size_t i = 0; i < face.vertices.size(); ++i) {
      const Vec3 p = xs[face.vertices[i]], q = xs[face.vertices[(i + 1) % face.vertices.size()]];
      *room = std::min(*room, (q - p).cross(tangent - p).norm() / (q - p).norm());
    }
  }
  const Mat3 rot = Eigen::Quaterniond::FromTwoVectors(Vec3::UnitZ(), n).toRotationMatrix();
  auto box = place(geometry::shapes::boxAround(Vec3::Zero(), Vec3(0.5 * a, 0.5 * a, 0.5 * height)),
                   tangent + (0.5 * height - delta) * n, rot);
  const Contact c = kernel.collide(box.body, t.body, nullptr);
  return {c.potential, c.normal};
}

struct LoopWork {
  double work = 0.0;       // closed-path integral of f.du + M.dtheta
  double magnitude = 0.0;  // integral of |f.du| + |M.dtheta|
  double work_without_torsion = 0.0;
};

// A moves around a closed loop: its centre on an ellipse in a tilted plane and, if `turn` > 0,
// its orientation on a closed loop of rotations; periodic trapezoid rule with n steps.
template <class K>
LoopWork loopWork(const K& kernel, const std::vector<Vec3>& a_points, const Placed& b,
                  const Vec3& centre, double radius, double turn, int n) {
  auto shape = std::make_unique<geometry::ConvexPolyhedron>(
      geometry::ConvexPolyhedron::fromPoints(a_points));
  const Vec3 e1 = Vec3(1, 0.3, -0.2).normalized();
  const Vec3 e2 = e1.cross(Vec3(0.2, -0.4, 1)).normalized();
  auto pose = [&](double th, Vec3& x, Mat3& rot) {
    x = centre + radius * (std::cos(th) * e1 + 0.6 * std::sin(th) * e2);
    rot = rotationAbout(Vec3(1, 0, 0), turn * std::sin(th)) *
          rotationAbout(Vec3(0, 1, 1), turn * (1 - std::cos(th)));
  };
  LoopWork w;
  std::vector<Vec3> storage;
  const double h = 2 * kPi / n, eps = 1e-6;
  for (int k = 0; k < n; ++k) {
    const double th = k * h;
    Vec3 x, xp, xm;
    Mat3 rot, rp, rm;
    pose(th, x, rot);
    pose(th + eps, xp, rp);
    pose(th - eps, xm, rm);
    const Vec3 dx = (xp - xm) / (2 * eps);
    const Mat3 skew = (rp - rm) / (2 * eps) * rot.transpose();
    const Vec3 omega(skew(2, 1), skew(0, 2), skew(1, 0));
    const Body body = placeBody(*shape, x, rot, storage);
    const auto res = kernel.evaluate(body, b.body);
    if (!res.contact.touching) continue;
    const Vec3 f = res.force;
    // Power of the force field: f.(velocity of A's frame origin) + M.omega with M about that
    // origin (the torsion included).
    const Vec3 arm = res.contact.point - x;
    const Vec3 moment = res.moment + arm.cross(f);
    const Vec3 moment_no_torsion = moment - res.torsion * res.contact.normal;
    w.work += h * (f.dot(dx) + moment.dot(omega));
    w.work_without_torsion += h * (f.dot(dx) + moment_no_torsion.dot(omega));
    w.magnitude += h * (std::abs(f.dot(dx)) + std::abs(moment.dot(omega)));
  }
  return w;
}

// Where A's frame origin goes for A (unrotated) to overlap B by about `depth` along `dir`.
inline Vec3 overlappingPosition(const std::vector<Vec3>& a_points, const Placed& b, const Vec3& dir,
                                double depth) {
  const auto wb = worldShape(b.body);
  const double t = touchingDistance(a_points, Mat3::Identity(), wb, dir) - depth;
  return wb.centroid() + t * dir - geometry::ConvexPolyhedron::fromPoints(a_points).centroid();
}

/// Zhao 5.1 in static form: an irregular tetrahedron whose ridge (-1,0,0)-(1,0,0) is on top, the
/// bisector of its two faces there vertical, but the faces of unequal area (1.28 and 0.64).
inline std::vector<Vec3> ridgeTetrahedron() {
  return {{-1, 0, 0}, {1, 0, 0}, {0.3, 0.8, -1.0}, {-0.5, -0.4, -0.5}};
}
/// A square pyramid (base 0.2, height 0.2) apex down at (0, 0, -delta): pressed onto the ridge.
inline std::vector<Vec3> pyramidOnRidge(double delta) {
  return geometry::shapes::squarePyramid(Vec3(0, 0, -delta), 0.2, 0.2,
                                         geometry::shapes::Apex::kDown);
}

struct RandomPair {
  Placed a, b;
};

// Two random polyhedra (8 to 40 vertices) in random orientations, A's centroid on a random line
// through B's, `depth` closer than touching.
inline RandomPair randomPair(std::uint64_t seed, double depth) {
  std::mt19937_64 rng(seed);
  std::uniform_int_distribution<int> nv(8, 40);
  const auto pa = geometry::shapes::randomConvex(nv(rng), seed * 3 + 1, {0.8, 0.6, 0.5}, 0.3);
  const auto pb = geometry::shapes::randomConvex(nv(rng), seed * 3 + 2, {1.0, 0.7, 0.6}, 0.3);
  const Mat3 ra = randomRotation(rng), rb = randomRotation(rng);
  const Vec3 dir = randomRotation(rng) * Vec3::UnitZ();
  auto b = place(pb, Vec3(0.1, -0.2, 0.3), rb);
  const auto wb = worldShape(b.body);
  const double t = touchingDistance(pa, ra, wb, dir) - depth;
  const Vec3 ca = geometry::ConvexPolyhedron::fromPoints(pa).centroid();
  auto a = place(pa, wb.centroid() + t * dir - ra * ca, ra);
  return {std::move(a), std::move(b)};
}

// --- checks both potential kernels must pass ------------------------------------------------

// The force is f = -grad E, E = penalty * integral over V of (phi_A + phi_B) dV (Zhao eq. 3 in
// divergence form), so the work along a closed path vanishes, rotations included when the
// torsion is kept.
template <class K>
void expectClosedLoopWorkVanishes(const K& kernel) {
  auto b = place(geometry::shapes::randomConvex(20, 5, {1, 0.8, 0.6}, 0.2));
  const auto a_points = geometry::shapes::randomConvex(14, 6, {0.6, 0.5, 0.4}, 0.2);
  const Vec3 centre = overlappingPosition(a_points, b, Vec3(0.3, 0.2, 1).normalized(), 0.15);
  for (double turn : {0.0, 0.15}) {
    const LoopWork w = loopWork(kernel, a_points, b, centre, 0.06, turn, 720);
    std::printf("turn %.2f: closed-loop work / path integral %.2e (torsion dropped: %.2e)\n", turn,
                w.work / w.magnitude, w.work_without_torsion / w.magnitude);
    ASSERT_GT(w.magnitude, 0.0);
    EXPECT_LT(std::abs(w.work), 1e-4 * w.magnitude);
  }
}

// Newton's third law: B on A gives the opposite force at the same point, for random pairs with
// seeds first..last (and the same depth, if `same_depth`).
template <class K>
void expectSwappingThePairReversesTheForce(const K& kernel, std::uint64_t first, std::uint64_t last,
                                           bool same_depth) {
  for (std::uint64_t seed = first; seed <= last; ++seed) {
    const RandomPair p = randomPair(seed, 0.1);
    const auto ab = kernel.evaluate(p.a.body, p.b.body);
    const auto ba = kernel.evaluate(p.b.body, p.a.body);
    const double size = p.a.body.circumradius() + p.b.body.circumradius();
    EXPECT_LT((ab.force + ba.force).norm(), 1e-12 * ab.force.norm());
    EXPECT_LT((ab.contact.point - ba.contact.point).norm(), 1e-12 * size);
    if (same_depth) {
      EXPECT_NEAR(ab.contact.depth, ba.contact.depth, 1e-12 * size);
    }
  }
}

// Scale-free: random pairs (seeds first..last) scaled by 1e-3 and 1e3 give the potential times
// s^2, the same normal, the point times s (and the depth times s, if `check_depth`).
template <class K>
void expectRandomPairsScaleWithTheUnit(const K& kernel, std::uint64_t first, std::uint64_t last,
                                       bool check_depth) {
  for (std::uint64_t seed = first; seed <= last; ++seed) {
    const RandomPair p = randomPair(seed, 0.1);
    const Contact r1 = kernel.collide(p.a.body, p.b.body, nullptr);
    for (double s : {1e-3, 1e3}) {
      std::vector<Vec3> va, vb;
      for (const Vec3& x : p.a.body.vertices) va.push_back(s * x);
      for (const Vec3& x : p.b.body.vertices) vb.push_back(s * x);
      auto a = place(va), b = place(vb);
      const Contact r = kernel.collide(a.body, b.body, nullptr);
      ASSERT_TRUE(r.touching);
      EXPECT_NEAR(r.potential, s * s * r1.potential, 1e-10 * s * s * r1.potential);
      EXPECT_LT(angleBetween(r.normal, r1.normal), 1e-10);
      EXPECT_LT((r.point - s * r1.point).norm(), 1e-10 * s);
      if (check_depth) {
        EXPECT_NEAR(r.depth, s * r1.depth, 1e-10 * s);
      }
    }
  }
}

// Unit cubes 1e-9 apart, with faces exactly touching (also turned, so touching up to round-off),
// and turned 45 deg side by side (boxes overlap, faces 0.19 apart): no contact.
template <class K>
void expectSeparatedAndTouchingCubesDoNotTouch(const K& kernel) {
  using geometry::shapes::cube;
  auto b = place(cube(1.0));
  for (double gap : {1e-9, 0.0}) {
    auto a = place(cube(1.0), Vec3(0.2, 0.1, 1.0 + gap));
    EXPECT_FALSE(kernel.collide(a.body, b.body, nullptr).touching) << gap;
  }
  std::mt19937_64 rng(3);
  for (int k = 0; k < 5; ++k) {
    const Mat3 rot = randomRotation(rng);
    const Vec3 t(0.3, -2.0, 7.0);
    auto bt = place(cube(1.0), t, rot);
    auto at = place(cube(1.0), t + rot * Vec3(0.2, 0.1, 1.0), rot);
    EXPECT_FALSE(kernel.collide(at.body, bt.body, nullptr).touching);
  }
  const Mat3 r45z = rotationAbout(Vec3::UnitZ(), kPi / 4);
  auto d1 = place(cube(1.0), Vec3::Zero(), r45z);
  auto d2 = place(cube(1.0), Vec3(0.8, 0.8, 0.3), r45z);
  EXPECT_FALSE(kernel.collide(d2.body, d1.body, nullptr).touching);
}

}  // namespace polydem::contact::testing
