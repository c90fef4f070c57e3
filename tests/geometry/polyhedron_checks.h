// Checks shared by the geometry tests: topological and geometric consistency of a polyhedron, and
// mass properties computed independently of mass_properties.cpp.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "polydem/geometry/convex_polyhedron.h"

namespace polydem::geometry::testing {

/// Every structural promise of convex_polyhedron.h, checked from scratch.
inline void expectValidPolyhedron(const ConvexPolyhedron& p) {
  const auto& vs = p.vertices();
  const auto& faces = p.faces();
  const auto& edges = p.edges();
  const int nv = static_cast<int>(vs.size());
  const double tol = 1e-9 * p.lengthScale();
  EXPECT_EQ(nv - static_cast<int>(edges.size()) + static_cast<int>(faces.size()), 2) << "Euler";

  for (std::size_t f = 0; f < faces.size(); ++f) {
    const Face& face = faces[f];
    const std::size_t n = face.vertices.size();
    ASSERT_GE(n, 3u);
    ASSERT_EQ(face.edges.size(), n);
    EXPECT_NEAR(face.normal.norm(), 1.0, 1e-14);
    for (std::size_t i = 0; i < n; ++i) {
      const Vec3& a = vs[face.vertices[i]];
      const Vec3& b = vs[face.vertices[(i + 1) % n]];
      const Vec3& c = vs[face.vertices[(i + 2) % n]];
      // Planar, and strictly convex counter-clockwise about the outward normal.
      EXPECT_NEAR(face.normal.dot(a), face.offset, tol) << "face " << f << " not planar";
      EXPECT_GT((b - a).cross(c - b).dot(face.normal), 0.0) << "face " << f << " not CCW/convex";
      // Edge i joins corners i and i + 1.
      const Edge& e = edges[face.edges[i]];
      const int lo = std::min(face.vertices[i], face.vertices[(i + 1) % n]);
      const int hi = std::max(face.vertices[i], face.vertices[(i + 1) % n]);
      EXPECT_EQ(e.v0, lo);
      EXPECT_EQ(e.v1, hi);
      const bool up = face.vertices[i] < face.vertices[(i + 1) % n];
      EXPECT_EQ(up ? e.f0 : e.f1, static_cast<int>(f));
    }
    // Outward: no vertex above the face plane.
    for (int v = 0; v < nv; ++v) EXPECT_LE(face.normal.dot(vs[v]) - face.offset, tol);
    EXPECT_GT(face.area, 0.0);
    EXPECT_NEAR(face.normal.dot(face.centroid), face.offset, tol);
  }
  // Adjacent faces are not coplanar (facets coplanar within 1e-10 of the size were merged): some
  // corner of one lies clearly below the plane of the other.
  for (const Edge& e : edges) {
    EXPECT_LT(e.v0, e.v1);
    ASSERT_NE(e.f0, e.f1);
    double depth = 0.0;
    for (int v : faces[e.f1].vertices) {
      depth = std::max(depth, faces[e.f0].offset - faces[e.f0].normal.dot(vs[v]));
    }
    EXPECT_GT(depth, 1e-11 * p.lengthScale()) << "faces " << e.f0 << ", " << e.f1 << " coplanar";
  }
  // Vertex fans: neighbours, edges and faces agree and go around the vertex.
  ASSERT_EQ(p.vertexEdges().size(), vs.size());
  for (int v = 0; v < nv; ++v) {
    const auto& ve = p.vertexEdges()[v];
    const auto& vf = p.vertexFaces()[v];
    const auto& vn = p.vertexNeighbours()[v];
    ASSERT_EQ(ve.size(), vn.size());
    ASSERT_EQ(vf.size(), vn.size());
    ASSERT_GE(vn.size(), 3u);
    EXPECT_EQ(*std::min_element(vn.begin(), vn.end()), vn[0]);
    const std::size_t k_max = vn.size();
    for (std::size_t k = 0; k < k_max; ++k) {
      const Edge& e = edges[ve[k]];
      EXPECT_TRUE((e.v0 == v && e.v1 == vn[k]) || (e.v1 == v && e.v0 == vn[k]));
      const auto& fv = faces[vf[k]].vertices;
      EXPECT_NE(std::find(fv.begin(), fv.end(), v), fv.end());
      EXPECT_NE(std::find(fv.begin(), fv.end(), vn[k]), fv.end());
      EXPECT_NE(std::find(fv.begin(), fv.end(), vn[(k + 1) % k_max]), fv.end());
    }
  }
  std::vector<int> degree(nv, 0);
  for (const Edge& e : edges) {
    ++degree[e.v0];
    ++degree[e.v1];
  }
  for (int v = 0; v < nv; ++v) EXPECT_EQ(degree[v], static_cast<int>(p.vertexEdges()[v].size()));
}

struct MassProperties {
  double volume = 0.0;
  Vec3 centroid = Vec3::Zero();
  Mat3 inertia = Mat3::Zero();
};

/// Mass properties by a decomposition different from the library's: each face is fanned about
/// its corner mean, each triangle spans a tetrahedron with the vertex mean of the polyhedron, and
/// the second moments come from the 4-point Gauss rule for tetrahedra (exact for quadratics).
inline MassProperties independentMassProperties(const ConvexPolyhedron& p) {
  const auto& vs = p.vertices();
  Vec3 apex = Vec3::Zero();
  for (const Vec3& v : vs) apex += v;
  apex /= static_cast<double>(vs.size());
  struct Tet {
    Vec3 a, b, c, d;
    double volume;
  };
  std::vector<Tet> tets;
  for (const Face& face : p.faces()) {
    Vec3 q = Vec3::Zero();
    for (int v : face.vertices) q += vs[v];
    q /= static_cast<double>(face.vertices.size());
    const std::size_t n = face.vertices.size();
    for (std::size_t i = 0; i < n; ++i) {
      const Vec3& b = vs[face.vertices[i]];
      const Vec3& c = vs[face.vertices[(i + 1) % n]];
      tets.push_back({apex, q, b, c, (q - apex).dot((b - apex).cross(c - apex)) / 6.0});
    }
  }
  MassProperties m;
  Vec3 moment = Vec3::Zero();
  for (const Tet& t : tets) {
    m.volume += t.volume;
    moment += t.volume * (t.a + t.b + t.c + t.d) / 4.0;
  }
  m.centroid = moment / m.volume;
  const double alpha = 0.5854101966249685, beta = 0.1381966011250105;
  Mat3 second = Mat3::Zero();
  for (const Tet& t : tets) {
    const Vec3 a = t.a - m.centroid, b = t.b - m.centroid, c = t.c - m.centroid,
               d = t.d - m.centroid;
    for (const Vec3& x :
         {Vec3(alpha * a + beta * (b + c + d)), Vec3(alpha * b + beta * (a + c + d)),
          Vec3(alpha * c + beta * (a + b + d)), Vec3(alpha * d + beta * (a + b + c))}) {
      second += 0.25 * t.volume * x * x.transpose();
    }
  }
  m.inertia = second.trace() * Mat3::Identity() - second;
  return m;
}

/// A rotation drawn from `rng` (uniform quaternion).
inline Mat3 randomRotation(std::mt19937_64& rng) {
  std::normal_distribution<double> normal;
  Quat q(normal(rng), normal(rng), normal(rng), normal(rng));
  return q.normalized().toRotationMatrix();
}

inline std::vector<Vec3> transformedPoints(const std::vector<Vec3>& points, const Mat3& r,
                                           const Vec3& t) {
  std::vector<Vec3> out;
  for (const Vec3& p : points) out.push_back(r * p + t);
  return out;
}

}  // namespace polydem::geometry::testing
