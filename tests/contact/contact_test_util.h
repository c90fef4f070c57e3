// Helpers shared by the contact-kernel tests: placed bodies that own their shape and world
// vertices, random rigid motions, and an independent reference for the minimum penetration:
// brute-force SAT over every face normal and every edge-edge cross product of the pair.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <random>
#include <vector>

#include "polydem/contact/contact.h"
#include "polydem/contact/contact_cases.h"
#include "polydem/geometry/convex_polyhedron.h"

namespace polydem::contact::testing {

/// A body that owns its shape and world vertices (not movable: the Body points into them).
class Placed {
 public:
  Placed(geometry::ConvexPolyhedron shape, const Vec3& position, const Mat3& rotation)
      : shape_(std::move(shape)) {
    body_ = placeBody(shape_, position, rotation, world_);
  }
  Placed(const Placed&) = delete;
  Placed& operator=(const Placed&) = delete;
  const Body& body() const { return body_; }
  const geometry::ConvexPolyhedron& shape() const { return shape_; }

 private:
  geometry::ConvexPolyhedron shape_;
  std::vector<Vec3> world_;
  Body body_;
};

/// A body whose shape is given by world vertices (identity placement).
inline std::unique_ptr<Placed> placeWorld(const std::vector<Vec3>& world) {
  return std::make_unique<Placed>(geometry::ConvexPolyhedron::fromPoints(world), Vec3::Zero(),
                                  Mat3::Identity());
}

/// The bodies of a contact case moved by x -> scale R x + t, with the shapes built from the
/// unit-size case and placed by (t, R) after scaling, so that the kernels see a real rotation.
struct CasePair {
  std::unique_ptr<Placed> a, b;
};
inline CasePair placeCase(const ContactCase& c, const Mat3& rotation = Mat3::Identity(),
                          const Vec3& translation = Vec3::Zero(), double scale = 1.0) {
  CasePair p;
  p.a = std::make_unique<Placed>(geometry::ConvexPolyhedron::fromPoints(c.a).scaled(scale),
                                 translation, rotation);
  p.b = std::make_unique<Placed>(geometry::ConvexPolyhedron::fromPoints(c.b).scaled(scale),
                                 translation, rotation);
  return p;
}

/// Uniformly distributed rotation (normalised Gaussian quaternion).
inline Mat3 randomRotation(std::mt19937_64& rng) {
  std::normal_distribution<double> g(0.0, 1.0);
  Quat q(g(rng), g(rng), g(rng), g(rng));
  q.normalize();
  return q.toRotationMatrix();
}

inline Vec3 randomUnit(std::mt19937_64& rng) {
  std::normal_distribution<double> g(0.0, 1.0);
  return Vec3(g(rng), g(rng), g(rng)).normalized();
}

/// Minimum penetration by the separating-axis theorem, brute force: every face normal of A and B
/// and the cross product of every edge of A with every edge of B whose arcs on the Gauss map
/// cross (Gregorius, GDC 2013: only those pairs span a face of A - B; the others are never the
/// minimum and only cost time), both signs. `normal` points from B
/// into A (A moves along it by `depth` to separate); depth < 0 is the separation along the best
/// axis (a lower bound of the distance). `runner_up` is the smallest depth over axes more than
/// 1e-6 rad away from `normal`: the minimum is unique when it is clearly larger than `depth`.
struct SatResult {
  double depth = std::numeric_limits<double>::infinity();
  Vec3 normal = Vec3::UnitZ();
  double runner_up = std::numeric_limits<double>::infinity();
};

/// max over B of n . b - min over A of n . a: how far A must move along n to clear B.
inline double overlapAlong(const Body& a, const Body& b, const Vec3& n) {
  double min_a = std::numeric_limits<double>::infinity();
  double max_b = -std::numeric_limits<double>::infinity();
  for (const Vec3& x : a.vertices) min_a = std::min(min_a, n.dot(x));
  for (const Vec3& x : b.vertices) max_b = std::max(max_b, n.dot(x));
  return max_b - min_a;
}

inline SatResult satPenetration(const Body& a, const Body& b) {
  std::vector<Vec3> axes;
  for (const auto& f : a.shape->faces()) axes.push_back(a.rotation * f.normal);
  for (const auto& f : b.shape->faces()) axes.push_back(b.rotation * f.normal);
  const auto& fa = a.shape->faces();
  const auto& fb = b.shape->faces();
  for (const auto& ea : a.shape->edges()) {
    const Vec3 da = a.vertices[ea.v1] - a.vertices[ea.v0];
    const Vec3 n0 = a.rotation * fa[ea.f0].normal, n1 = a.rotation * fa[ea.f1].normal;
    const Vec3 n1xn0 = n1.cross(n0);
    for (const auto& eb : b.shape->edges()) {
      // The arcs n0-n1 of A's edge and -m0 to -m1 of B's (A - B takes B's normals negated).
      const Vec3 m0 = -(b.rotation * fb[eb.f0].normal), m1 = -(b.rotation * fb[eb.f1].normal);
      const Vec3 m1xm0 = m1.cross(m0);
      const double cba = m0.dot(n1xn0), dba = m1.dot(n1xn0);
      const double adc = n0.dot(m1xm0), bdc = n1.dot(m1xm0);
      if (!(cba * dba < 0.0 && adc * bdc < 0.0 && cba * bdc > 0.0)) continue;
      const Vec3 db = b.vertices[eb.v1] - b.vertices[eb.v0];
      const Vec3 n = da.cross(db);
      if (n.norm() > 1e-9 * da.norm() * db.norm()) axes.push_back(n.normalized());
    }
  }
  std::vector<std::pair<double, Vec3>> candidates;
  candidates.reserve(2 * axes.size());
  for (const Vec3& n : axes) {
    // Both signs from one pass: along n A must clear max_b - min_a, along -n max_a - min_b.
    double min_a = std::numeric_limits<double>::infinity(), max_a = -min_a;
    double min_b = min_a, max_b = max_a;
    for (const Vec3& x : a.vertices) {
      const double h = n.dot(x);
      min_a = std::min(min_a, h);
      max_a = std::max(max_a, h);
    }
    for (const Vec3& x : b.vertices) {
      const double h = n.dot(x);
      min_b = std::min(min_b, h);
      max_b = std::max(max_b, h);
    }
    candidates.emplace_back(max_b - min_a, n);
    candidates.emplace_back(max_a - min_b, Vec3(-n));
  }
  SatResult r;
  for (const auto& [d, n] : candidates) {
    if (d < r.depth) {
      r.depth = d;
      r.normal = n;
    }
  }
  for (const auto& [d, n] : candidates) {
    if (d < r.runner_up && angleBetween(n, r.normal) > 1e-6) r.runner_up = d;
  }
  return r;
}

}  // namespace polydem::contact::testing
