// Certificate of global optimality for the FCP's local search (see fcp_detail.h).
//
// The penetration of two convex bodies, pen(A, B) = min over unit m of h_B(m) + h_A(-m) (h the
// support function), is what the common plane of overlapping bodies realises: -gap. The local
// search ends at a local minimum of that function over the candidate normals; several local minima
// exist in general (an elongated overlap has one per face of the Minkowski difference whose foot
// point lies inside it). A lower bound proves a local minimum global: for convex X in A and Y in B,
// h_X <= h_A and h_Y <= h_B, so pen(X, Y) <= pen(A, B). The pieces used here are cheap and tight
// for ordinary contacts, where the overlap is shallow compared with the contact features:
//   1. a closest vertex of one body and the whole other body: pen = the depth of the vertex
//      inside the body, min over the body's faces (vertex-face, edge-face, face-face); for
//      face-face also a ball in the middle of the overlap, inside both bodies: pen >= its diameter;
//   2. a piece of each body around its contact feature: for a vertex, the hull of the vertex and
//      its neighbours; for an edge, the tetrahedron
//      of the edge and the farthest corner of each of its two faces (the wedge a crossing edge
//      must clear); for a face, the pyramid from the face to the body's centroid. pen of the two
//      pieces follows from the separating-axis theorem over their few face normals and edge-edge
//      cross products (edge-edge contacts, and face contacts with no corner inside the other body).
// When the bound falls short (vertex-vertex and vertex-edge contacts, deep overlaps, features that
// barely overlap) the caller scans every candidate instead.
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "polydem/contact/fcp/fcp_detail.h"

namespace polydem::contact::fcp_detail {

namespace {

/// Whether x lies at least `target` inside `body` (distance to every face plane).
bool deeperThan(const Body& body, const Vec3& x, double target) {
  const Vec3 local = body.rotation.transpose() * (x - body.position);
  for (const auto& face : body.shape->faces()) {
    if (face.offset - face.normal.dot(local) < target) return false;
  }
  return true;
}

/// Largest face feature (closest-vertex set) the piece test handles; a larger one skips step 2.
constexpr int kMaxFeature = 32;

/// A convex piece of a body: its corners, a superset of its face normals (each checked both ways)
/// and its edges (pairs of corners).
struct Piece {
  std::array<Vec3, kMaxFeature + 1> p;
  std::array<Vec3, kMaxFeature + 8> faces;
  std::array<std::pair<int, int>, 2 * kMaxFeature> edges;
  int points = 0, face_count = 0, edge_count = 0;
  void addFace(const Vec3& normal) { faces[face_count++] = normal.normalized(); }
  void addEdge(int i, int j) { edges[edge_count++] = {i, j}; }
};

/// min and max of m . x over the corners.
std::pair<double, double> range(const Piece& x, const Vec3& m) {
  double lo = std::numeric_limits<double>::infinity();
  double hi = -lo;
  for (int i = 0; i < x.points; ++i) {
    const double v = m.dot(x.p[i]);
    lo = std::min(lo, v);
    hi = std::max(hi, v);
  }
  return {lo, hi};
}

/// Corners of the vertex piece besides the vertex: its first neighbours (any subset is valid).
constexpr int kStarNeighbours = 6;

/// Vertex feature v: the hull of v and its neighbours (the vertex's star, which a vertex inside
/// the other body near one of its faces' edges cannot leave sideways). Its face normals are among
/// those of the triangles of corners and its edges among the pairs of corners.
void vertexPiece(const Body& body, int v, Piece& out) {
  out.p[0] = body.vertices[v];
  out.points = 1;
  for (int u : body.shape->vertexNeighbours()[v]) {
    if (out.points > kStarNeighbours) break;
    out.p[out.points++] = body.vertices[u];
  }
  for (int i = 0; i < out.points; ++i) {
    for (int j = i + 1; j < out.points; ++j) {
      out.addEdge(i, j);
      for (int l = j + 1; l < out.points; ++l) {
        const Vec3 c = (out.p[j] - out.p[i]).cross(out.p[l] - out.p[i]);
        if (c.squaredNorm() > 0.0) out.addFace(c);
      }
    }
  }
}

/// Edge feature (v0, v1): the tetrahedron spanned by the edge and, in each of its two faces, the
/// corner farthest from the edge's line. Fatter than the edge alone: a crossing edge must clear
/// both faces of the wedge, not just a line.
void edgePiece(const Body& body, int v0, int v1, Piece& out) {
  const geometry::Edge& edge = body.shape->edges()[edgeBetween(body, v0, v1)];
  const Vec3 a = body.vertices[v0], dir = (body.vertices[v1] - a).normalized();
  out.p[0] = a;
  out.p[1] = body.vertices[v1];
  out.points = 2;
  for (int f : {edge.f0, edge.f1}) {
    int far = v0;
    double best = -1.0;
    for (int v : body.shape->faces()[f].vertices) {
      const Vec3 d = body.vertices[v] - a;
      const double off_line = (d - d.dot(dir) * dir).squaredNorm();
      if (off_line > best) {
        best = off_line;
        far = v;
      }
    }
    out.p[out.points++] = body.vertices[far];
  }
  for (int i = 0; i < 4; ++i) {
    for (int j = i + 1; j < 4; ++j) out.addEdge(i, j);
  }
  const auto triangle = [&](int i, int j, int l) {
    out.addFace((out.p[j] - out.p[i]).cross(out.p[l] - out.p[i]));
  };
  triangle(0, 1, 2);
  triangle(0, 1, 3);
  triangle(0, 2, 3);
  triangle(1, 2, 3);
}

/// Face feature (k >= 3 closest vertices): the pyramid from the polygon (ordered in the plane) to
/// the body's centroid.
void facePiece(const Body& body, std::span<const int> band, const geometry::PlaneFrame& frame,
               Piece& out) {
  thread_local std::vector<Vec3> points;
  thread_local std::vector<int> order;
  points.clear();
  for (int v : band) points.push_back(body.vertices[v]);
  const int k = convexOrder(points, frame, order);
  for (int i = 0; i < k; ++i) out.p[i] = points[order[i]];
  const Vec3 apex = body.centroid();
  out.p[k] = apex;
  out.points = k + 1;
  Vec3 newell = Vec3::Zero();
  for (int i = 0; i < k; ++i) {
    const int j = (i + 1) % k;
    newell += (out.p[i] - out.p[0]).cross(out.p[j] - out.p[0]);
    out.addFace((out.p[i] - apex).cross(out.p[j] - apex));
    out.addEdge(i, j);
    out.addEdge(i, k);
  }
  if (k >= 3) out.addFace(newell);
}

/// The piece of `body` spanned by its contact feature (closest vertices `band`).
bool makePiece(const Body& body, std::span<const int> band, const geometry::PlaneFrame& frame,
               Piece& out) {
  out.points = out.face_count = out.edge_count = 0;
  if (band.size() == 1) {
    vertexPiece(body, band[0], out);
  } else if (band.size() == 2) {
    edgePiece(body, band[0], band[1], out);
  } else if (static_cast<int>(band.size()) <= kMaxFeature) {
    facePiece(body, band, frame, out);
  } else {
    return false;
  }
  return true;
}

/// Whether pen(X, Y) >= target for X in A (above) and Y in B (below): the separating-axis theorem
/// over the face normals of both pieces and the cross products of their edges, each both ways;
/// any other direction gives a larger overlap.
bool penetrationAtLeast(const Piece& x, const Piece& y, double target) {
  int tried = 0;
  // For unit m, the overlap along m is max_Y m.y - min_X m.x; along -m it is max_X - min_Y.
  const auto both_ways_fine = [&](const Vec3& m) {
    ++tried;
    const auto [ylo, yhi] = range(y, m);
    const auto [xlo, xhi] = range(x, m);
    return yhi - xlo >= target && xhi - ylo >= target;
  };
  for (int i = 0; i < x.face_count; ++i) {
    if (!both_ways_fine(x.faces[i])) return false;
  }
  for (int i = 0; i < y.face_count; ++i) {
    if (!both_ways_fine(y.faces[i])) return false;
  }
  for (int i = 0; i < x.edge_count; ++i) {
    const Vec3 ex = x.p[x.edges[i].second] - x.p[x.edges[i].first];
    for (int j = 0; j < y.edge_count; ++j) {
      const Vec3 ey = y.p[y.edges[j].second] - y.p[y.edges[j].first];
      const Vec3 c = ex.cross(ey);
      const double norm = c.norm();
      if (norm <= kFcpParallelSine * ex.norm() * ey.norm()) continue;
      if (!both_ways_fine(c / norm)) return false;
    }
  }
  // No candidate at all: X - Y is flat or a point (a vertex against a vertex), no penetration.
  return tried > 0;
}

}  // namespace

bool certifyMinimumPenetration(const Body& a, const Body& b, const PlaneFeatures& f, double slack) {
  const double target = f.depth - slack;
  // 1. A closest vertex deep enough inside the other body, from the feature of lower dimension
  //    (the vertex of vertex-face, the edge of edge-face, either face of face-face). Edge-edge
  //    skips it: the ends of crossing edges lie outside the other body.
  const auto na = f.band_a.size(), nb = f.band_b.size();
  if (na <= nb && !(na == 2 && nb == 2)) {
    for (int v : f.band_a) {
      if (deeperThan(b, a.vertices[v], target)) return true;
    }
  }
  if (nb <= na && !(na == 2 && nb == 2)) {
    for (int v : f.band_b) {
      if (deeperThan(a, b.vertices[v], target)) return true;
    }
  }
  // 1b. Face-face: a ball of diameter `target` about the middle of the two contact faces (at the
  //     mid-plane), inside both bodies: no translation shorter than its diameter separates them.
  if (na >= 3 && nb >= 3) {
    Vec3 mean_a = Vec3::Zero(), mean_b = Vec3::Zero();
    for (int v : f.band_a) mean_a += a.vertices[v];
    for (int v : f.band_b) mean_b += b.vertices[v];
    mean_a /= static_cast<double>(na);
    mean_b /= static_cast<double>(nb);
    const Vec3 middle = 0.5 * (mean_a + mean_b);
    if (deeperThan(a, middle, 0.5 * target) && deeperThan(b, middle, 0.5 * target)) return true;
  }
  // 2. The pieces spanned by the two contact features.
  const auto frame = geometry::PlaneFrame::make(f.normal, a.vertices[f.band_a[0]]);
  thread_local Piece pa, pb;
  if (!makePiece(a, f.band_a, frame, pa) || !makePiece(b, f.band_b, frame, pb)) return false;
  return penetrationAtLeast(pa, pb, target);
}

}  // namespace polydem::contact::fcp_detail
