#include "polydem/contact/gjk/epa.h"

#include <cmath>
#include <cstdint>
#include <limits>

namespace polydem::contact {

namespace {

constexpr int kMaxFaces = 2 * kEpaMaxVertices;  // Euler: a triangulated sphere has 2V - 4 faces
constexpr double kInfinity = std::numeric_limits<double>::infinity();
/// A face whose doubled area is below this fraction of its longest edge squared is flat to
/// round-off: its normal means nothing, it is never the closest face and is deleted when reached.
constexpr double kFlatFace = 1e-14;
/// Next and previous corner of a triangle (no integer division in the hot loops).
constexpr int kNext[3] = {1, 2, 0};
constexpr int kPrev[3] = {2, 0, 1};

/// Triangle of the polytope, counter-clockwise seen from outside.
struct Face {
  Vec3 n;       // unit outward normal
  double dist;  // n . x on the face: the plane's signed distance from the origin; +inf when
                // the face is deleted or flat, so that the closest-face scan skips it
  int v[3];
  int adj[3];                // face across edge i, which runs v[i] -> v[i+1]
  std::uint8_t adj_edge[3];  // index of that edge in the neighbour
  bool alive;
  bool flat;
};

struct HorizonEdge {
  int face;  // a face that stays
  int edge;  // its edge on the horizon
};

/// The expanding polytope in fixed arrays. Deleted face slots are reused.
class Polytope {
 public:
  SupportPoint vertex[kEpaMaxVertices];
  int num_vertices = 0;
  Face face[kMaxFaces];
  int num_faces = 0;  // high-water mark of used slots

  /// The initial tetrahedron; its orientation is fixed here.
  void init(const Simplex& s) {
    const Vec3 e1 = s.p[1].w - s.p[0].w, e2 = s.p[2].w - s.p[0].w, e3 = s.p[3].w - s.p[0].w;
    const bool positive = e1.dot(e2.cross(e3)) > 0.0;
    for (int m = 0; m < 4; ++m) vertex[m] = s.p[m];
    if (positive) std::swap(vertex[1], vertex[2]);  // now (0,1,2) faces away from vertex 3
    num_vertices = 4;
    // Faces and, for each edge i of each face, the neighbouring face and the edge's index there.
    static constexpr int kTet[4][3] = {{0, 1, 2}, {0, 3, 1}, {0, 2, 3}, {1, 3, 2}};
    static constexpr int kAdj[4][3] = {{1, 3, 2}, {2, 3, 0}, {0, 3, 1}, {1, 2, 0}};
    static constexpr int kAdjEdge[4][3] = {{2, 2, 0}, {2, 0, 0}, {2, 1, 0}, {1, 1, 1}};
    for (int f = 0; f < 4; ++f) {
      newFace(kTet[f][0], kTet[f][1], kTet[f][2]);
      for (int i = 0; i < 3; ++i) {
        face[f].adj[i] = kAdj[f][i];
        face[f].adj_edge[i] = static_cast<std::uint8_t>(kAdjEdge[f][i]);
      }
    }
  }

  int closestFace() const {
    int best = -1;
    double best_dist = kInfinity;
    for (int f = 0; f < num_faces; ++f) {
      if (face[f].dist < best_dist) {
        best_dist = face[f].dist;
        best = f;
      }
    }
    return best;
  }

  /// Adds vertex `w` seen from face `f`: deletes the faces visible from it (connected to f) and
  /// fans new faces from the horizon to it. False if the polytope would become inconsistent
  /// (round-off made the visible region other than a disc) or full; it is then left broken.
  bool expand(int f, const SupportPoint& w) {
    if (num_vertices == kEpaMaxVertices) return false;
    const int vw = num_vertices++;
    vertex[vw] = w;
    num_horizon_ = 0;
    num_free_ = 0;
    remove(f);
    for (int i = 0; i < 3; ++i) silhouette(face[f].adj[i], face[f].adj_edge[i], w.w);
    const int nh = num_horizon_;
    if (nh < 3 || num_free_ + (kMaxFaces - num_faces) < nh) return false;
    for (int k = 0; k < nh; ++k) {
      const HorizonEdge& h = horizon_[k];
      const HorizonEdge& next = horizon_[k + 1 == nh ? 0 : k + 1];
      if (face[h.face].v[h.edge] != face[next.face].v[kNext[next.edge]]) return false;
    }
    int first = -1, previous = -1;
    for (int k = 0; k < nh; ++k) {
      const HorizonEdge h = horizon_[k];
      Face& g = face[h.face];
      const int nf = newFace(g.v[kNext[h.edge]], g.v[h.edge], vw);
      face[nf].adj[0] = h.face;
      face[nf].adj_edge[0] = static_cast<std::uint8_t>(h.edge);
      g.adj[h.edge] = nf;
      g.adj_edge[h.edge] = 0;
      if (previous >= 0) {
        face[previous].adj[1] = nf;
        face[previous].adj_edge[1] = 2;
        face[nf].adj[2] = previous;
        face[nf].adj_edge[2] = 1;
      } else {
        first = nf;
      }
      previous = nf;
    }
    face[previous].adj[1] = first;
    face[previous].adj_edge[1] = 2;
    face[first].adj[2] = previous;
    face[first].adj_edge[2] = 1;
    return true;
  }

 private:
  int free_[kMaxFaces];
  int num_free_ = 0;
  HorizonEdge horizon_[kMaxFaces];
  int num_horizon_ = 0;

  int newFace(int a, int b, int c) {
    const int f = num_free_ > 0 ? free_[--num_free_] : num_faces++;
    Face& F = face[f];
    F.v[0] = a;
    F.v[1] = b;
    F.v[2] = c;
    F.alive = true;
    const Vec3& pa = vertex[a].w;
    const Vec3& pb = vertex[b].w;
    const Vec3& pc = vertex[c].w;
    const Vec3 ab = pb - pa, ac = pc - pa;
    const Vec3 n = ab.cross(ac);
    const double length = n.norm();
    const double longest2 =
        std::max(std::max(ab.squaredNorm(), ac.squaredNorm()), (pc - pb).squaredNorm());
    F.flat = !(length > kFlatFace * longest2);
    if (F.flat) {
      F.n = Vec3::Zero();
      F.dist = kInfinity;
    } else {
      F.n = n / length;
      F.dist = F.n.dot(pa + pb + pc) / 3.0;
    }
    return f;
  }

  void remove(int f) {
    face[f].alive = false;
    face[f].dist = kInfinity;
    free_[num_free_++] = f;
  }

  /// Van den Bergen's silhouette walk: entered into face f through its edge e from a deleted face.
  /// Visible faces are deleted and walked on through their other two edges, in order, so that the
  /// horizon comes out as one counter-clockwise loop.
  void silhouette(int f, int e, const Vec3& w) {
    Face& F = face[f];
    if (!F.alive) return;
    if (!F.flat && F.n.dot(w) - F.dist <= 0.0) {
      horizon_[num_horizon_++] = {f, e};
      return;
    }
    remove(f);
    silhouette(F.adj[kNext[e]], F.adj_edge[kNext[e]], w);
    silhouette(F.adj[kPrev[e]], F.adj_edge[kPrev[e]], w);
  }
};

/// Turns GJK's simplex into a tetrahedron enclosing the origin (Bullet's and libccd's "blow-up"):
/// a segment through the origin gets the support point farthest from its line, a triangle the
/// support point farthest from its plane. False when A - B is flat there to within `tolerance`,
/// i.e. the origin lies on its boundary: touching, not penetrating.
bool blowUp(MinkowskiSupport& support, Simplex& s, double tolerance) {
  if (s.size == 1) return false;  // the origin is (within tolerance) a support point: boundary
  if (s.size == 2) {
    const Vec3 d = s.p[1].w - s.p[0].w;
    const double length = d.norm();
    if (!(length > tolerance)) return false;
    int k = 0;
    for (int m = 1; m < 3; ++m) {
      if (std::abs(d[m]) < std::abs(d[k])) k = m;
    }
    const Vec3 u1 = d.cross(Vec3::Unit(k)).normalized();
    const Vec3 u2 = (d / length).cross(u1);
    double best = 0.0;
    for (const Vec3& u : {u1, u2, Vec3(-u1), Vec3(-u2)}) {
      const SupportPoint w = support(u);
      const double h = (w.w - s.p[0].w).cross(d).norm() / length;
      if (h > best) {
        best = h;
        s.p[2] = w;
      }
    }
    if (!(best > tolerance)) return false;
    s.size = 3;
  }
  if (s.size == 3) {
    const Vec3 n = (s.p[1].w - s.p[0].w).cross(s.p[2].w - s.p[0].w);
    if (!(n.squaredNorm() > 0.0)) return false;
    const Vec3 u = n.normalized();
    const SupportPoint up = support(u);
    const SupportPoint down = support(-u);
    const double h_up = u.dot(up.w - s.p[0].w), h_down = -u.dot(down.w - s.p[0].w);
    if (!(std::max(h_up, h_down) > tolerance)) return false;
    s.p[3] = h_up >= h_down ? up : down;
    s.size = 4;
  }
  return true;
}

/// Barycentric coordinates of p (in the plane of the face) with respect to its corners.
Vec3 barycentric(const Polytope& P, const int v[3], const Vec3& p) {
  const Vec3& w0 = P.vertex[v[0]].w;
  const Vec3& w1 = P.vertex[v[1]].w;
  const Vec3& w2 = P.vertex[v[2]].w;
  const Vec3 n = (w1 - w0).cross(w2 - w0);
  const double nn = n.squaredNorm();
  const double l0 = n.dot((w1 - p).cross(w2 - p)) / nn;
  const double l1 = n.dot((w2 - p).cross(w0 - p)) / nn;
  return {l0, l1, 1.0 - l0 - l1};
}

}  // namespace

EpaResult epaPenetration(MinkowskiSupport& support, const Simplex& simplex, double tolerance) {
  EpaResult r;
  Simplex s = simplex;
  if (!blowUp(support, s, tolerance)) return r;  // touching: not penetrating

  Polytope P;
  P.init(s);
  int best = -1;
  bool intact = true;  // the faces are still those of the polytope `best` belongs to
  for (;;) {
    const int f = P.closestFace();
    if (f < 0) {  // every face flat: cannot happen for a tetrahedron of non-zero volume
      r.converged = false;
      break;
    }
    best = f;
    const Face& F = P.face[f];
    const SupportPoint w = support(F.n);
    r.lowest_a = w.ia;  // along -normal = F.n for A, along normal = -F.n for B
    r.highest_b = w.ib;
    if (F.n.dot(w.w) - F.dist <= tolerance) break;
    bool known = false;
    for (int i = 0; i < 3; ++i) {
      const SupportPoint& c = P.vertex[F.v[i]];
      known = known || (c.ia == w.ia && c.ib == w.ib);
    }
    if (known) break;
    ++r.iterations;
    // The face record is read below even if expand() breaks the polytope: keep a copy.
    const Face kept = F;
    if (!P.expand(f, w)) {
      P.face[f] = kept;
      r.converged = false;
      intact = false;
      break;
    }
  }
  if (best < 0) return r;

  const Face& F = P.face[best];
  const Vec3 c = F.dist * F.n;  // the origin's projection onto the closest face, Keissar eq. 2.1
  int f = best;
  Vec3 xi = barycentric(P, P.face[f].v, c);
  // Coplanar neighbours tie for the closest face; c lies in one of them: walk to it so that the
  // weights are those of the triangle holding c (at most a few steps on a flat region).
  for (int step = 0; intact && step < 16 && xi.minCoeff() < -1e-12; ++step) {
    int i = 0;
    xi.minCoeff(&i);
    const int edge = kNext[i];  // the edge opposite corner i
    const int g = P.face[f].adj[edge];
    const Face& G = P.face[g];
    if (!G.alive || G.flat || std::abs(G.n.dot(c) - G.dist) > tolerance) break;
    f = g;
    xi = barycentric(P, G.v, c);
  }
  xi = xi.cwiseMax(0.0);
  xi /= xi.sum();
  Vec3 ca = Vec3::Zero(), cb = Vec3::Zero();
  for (int i = 0; i < 3; ++i) {
    const SupportPoint& v = P.vertex[P.face[f].v[i]];
    ca += xi[i] * support.a().vertices[v.ia];  // Keissar eq. 2.2
    cb += xi[i] * support.b().vertices[v.ib];
  }
  r.normal = -F.n;
  r.depth = F.dist;
  r.touching = r.depth > 0.0;
  r.point = 0.5 * (ca + cb);
  return r;
}

}  // namespace polydem::contact
