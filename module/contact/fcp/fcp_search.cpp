// The FCP search (Nezami et al. 2004): local moves between candidate common planes, a certificate
// of global optimality, and an exact scan of the candidates when the certificate fails.
//
// With D = B - A (Minkowski difference), gap(n) = min_A n.a - max_B n.b = -h_D(n). The candidates
// that matter are the face normals of D: faces of A (normal -u, u outward), faces of B (normal u)
// and the pairs of an edge of A and an edge of B whose arcs on the Gauss sphere cross (Minkowski
// faces). At a plane n the vertex of D supporting n is (closest vertices of B) - (closest of A);
// the faces of D around it are built from the faces and edges at those vertices, and one of them
// is at least as good as n (n lies in their normal cone). A move to the best one strictly raises
// the gap, so the walk ends, at a local maximum of the gap. For separated pairs any positive gap
// proves separation. For overlapping pairs the local maximum need not be global (one per face of
// D whose foot point lies inside it); fcp_certificate.cpp proves it global or the scan runs.
//
// Order of work: (1) the plane the start plane rests on (the warm start's feature) and its
// certificate: a persistent contact ends here; (2) local moves, unless the inscribed balls
// overlap (deep overlaps, which the certificate cannot prove); (3) the certificate; (4) the exact
// scan, pruned by bounds from the inscribed balls, its edge pairs found by walking the overlay
// of the two Gauss maps instead of trying every pair.
#include <algorithm>
#include <cmath>
#include <limits>

#include "polydem/contact/fcp/fcp.h"
#include "polydem/contact/fcp/fcp_detail.h"

namespace polydem::contact {

namespace {

using fcp_detail::climbMax;
using fcp_detail::collectBand;
using fcp_detail::coneSide;
using fcp_detail::EdgeCone;
using fcp_detail::edgeCone;
using fcp_detail::Extreme;
using fcp_detail::maxOverArc;
using fcp_detail::worldNormals;

/// Local moves before the full scan takes over (a cold start on 40-vertex bodies needs < 10).
constexpr int kMaxMoves = 64;

/// A candidate normal with its gap and a closest vertex of each body (seeds for the bands).
struct Candidate {
  Vec3 normal = Vec3::UnitZ();
  double gap = -std::numeric_limits<double>::infinity();
  int ia = 0, ib = 0;
};

/// A plane of the search: the normal, the closest vertices of each body and their levels.
struct Plane {
  Vec3 n = Vec3::UnitZ();
  int ia = 0, ib = 0;
  double level_a = 0.0, level_b = 0.0;
  double gap() const { return level_a - level_b; }
};

struct SearchScratch {
  std::vector<int> band_a, band_b, edges_a, edges_b;
  std::vector<std::pair<int, int>> faces_a, faces_b;  // (face, a vertex of it)
  std::vector<EdgeCone> cones_a, cones_b;
  std::vector<Vec3> normals_a, normals_b;
  std::vector<int> support_b;  // per face of A: B's support along its inward normal
};

/// Per-thread buffers (polydem runs one thread per rank): no allocation once they have grown.
SearchScratch& searchScratch() {
  thread_local SearchScratch s;
  return s;
}

class FcpSearch {
 public:
  FcpSearch(const Body& a, const Body& b, FcpTrace& trace)
      : a_(a), b_(b), trace_(trace), w_(searchScratch()) {
    const double scale = fcp_detail::lengthScale(a, b);
    band_ = FcpTolerance::kBand * scale;
    improve_ = FcpTolerance::kImprove * scale;
    slack_ = FcpTolerance::kCertify * scale;
    ca_ = a.toWorld(a.shape->incenter());
    cb_ = b.toWorld(b.shape->incenter());
    ra_ = a.shape->inradius();
    rb_ = b.shape->inradius();
  }

  /// Whether the inscribed balls overlap: the pair overlaps by at least as much.
  bool ballsOverlap() const { return (ca_ - cb_).norm() < ra_ + rb_; }

  Plane start(const Vec3& n) const {
    const Extreme lo = fcp_detail::supportMax(a_, -n), hi = fcp_detail::supportMax(b_, n);
    return {n, lo.index, hi.index, -lo.value, hi.value};
  }

  Plane fromCandidate(const Candidate& c) {
    Plane s{c.normal, c.ia, c.ib, 0.0, 0.0};
    settle(s);
    return s;
  }

  /// Collects the closest-vertex bands of the plane and its exact levels.
  void settle(Plane& s) {
    const Vec3 m = -s.n;
    const Extreme lo = collectBand(a_, m, s.ia, m.dot(a_.vertices[s.ia]) - band_, w_.band_a);
    const Extreme hi = collectBand(b_, s.n, s.ib, s.n.dot(b_.vertices[s.ib]) - band_, w_.band_b);
    s.ia = lo.index;
    s.ib = hi.index;
    s.level_a = -lo.value;
    s.level_b = hi.value;
  }

  bool improves(const Candidate& c, const Plane& s) const { return c.gap > s.gap() + improve_; }

  bool certify(const Plane& s) const {
    const fcp_detail::PlaneFeatures f{w_.band_a, w_.band_b, s.n, -s.gap()};
    return fcp_detail::certifyMinimumPenetration(a_, b_, f, slack_);
  }

  /// Best candidate among the faces and edges at the closest vertices of the settled plane `s`.
  Candidate bestLocal(const Plane& s) {
    gatherFeatures(a_, w_.band_a, w_.faces_a, w_.edges_a);
    gatherFeatures(b_, w_.band_b, w_.faces_b, w_.edges_b);
    // Only candidates that could improve on s count; the bounds of bestOverall skip the others.
    const double floor = s.gap() + improve_;
    Candidate best;
    for (const auto& [f, v] : w_.faces_a) {
      const Vec3 u = a_.faceNormal(f);
      if (faceOfABound(u, v) > floor) consider(faceOfA(u, v, s.ib), best);
    }
    for (const auto& [f, v] : w_.faces_b) {
      const Vec3 u = b_.faceNormal(f);
      if (faceOfBBound(u, v) > floor) consider(faceOfB(u, v, s.ia), best);
    }
    w_.cones_a.clear();
    for (int e : w_.edges_a) {
      const geometry::Edge& edge = a_.shape->edges()[e];
      const Vec3 u0 = a_.faceNormal(edge.f0), u1 = a_.faceNormal(edge.f1);
      if (edgeOfABound(u0, u1, edge.v0) > floor) w_.cones_a.push_back(edgeCone(a_, e, u0, u1));
    }
    w_.cones_b.clear();
    for (int e : w_.edges_b) {
      const geometry::Edge& edge = b_.shape->edges()[e];
      const Vec3 u0 = b_.faceNormal(edge.f0), u1 = b_.faceNormal(edge.f1);
      if (edgeOfBBound(u0, u1, edge.v0) > floor) w_.cones_b.push_back(edgeCone(b_, e, u0, u1));
    }
    edgePairs(best);
    return best;
  }

  /// The candidates of the features the plane rests on: the face of A at its closest vertices
  /// facing -n most squarely, the face of B facing n most squarely and, unless a face is closest,
  /// the cross product of the flattest edges at the closest vertices. A warm start's plane, moved
  /// a little with the bodies, is usually one of them.
  Candidate bestNatural(const Plane& s) {
    Candidate best;
    const auto [fa, va] = squarestFace(a_, w_.band_a, -s.n);
    const auto [fb, vb] = squarestFace(b_, w_.band_b, s.n);
    consider(faceOfA(a_.faceNormal(fa), va, s.ib), best);
    consider(faceOfB(b_.faceNormal(fb), vb, s.ia), best);
    if (w_.band_a.size() <= 2 && w_.band_b.size() <= 2) {
      w_.cones_a.assign(1, edgeCone(a_, flattestEdge(a_, w_.band_a, s.n)));
      w_.cones_b.assign(1, edgeCone(b_, flattestEdge(b_, w_.band_b, s.n)));
      edgePairs(best);
    }
    return best;
  }

  /// Best candidate of all that can beat the plane `s`: the faces of D = B - A. Every face of A
  /// (B's support along it climbed) and of B; then, for each edge of A, the edges of B whose
  /// normal arcs its own arc crosses on the Gauss sphere (the overlay of the two Gauss maps),
  /// found by walking B's support along the arc. Faces and edges that cannot beat the best gap
  /// are skipped by a bound: with the inscribed balls (c_A, r_A), (c_B, r_B), the overlap along m,
  /// h(m) = max_B m.b - min_A m.a, is at least m.c_B + r_B - min_A m.a and at least
  /// max_B m.b - m.c_A + r_A; for a face the other term is exact, for an edge of A it is exact
  /// over the edge's arc, where the bound's least value has a closed form (maxOverArc).
  Candidate bestOverall(const Plane& s) {
    Candidate best{s.n, s.gap(), s.ia, s.ib};
    const auto& faces_a = a_.shape->faces();
    const auto& faces_b = b_.shape->faces();
    worldNormals(a_, w_.normals_a);
    worldNormals(b_, w_.normals_b);
    w_.support_b.assign(faces_a.size(), -1);
    hint_b_ = s.ib;
    for (std::size_t f = 0; f < faces_a.size(); ++f) {
      const Vec3& u = w_.normals_a[f];
      const int v = faces_a[f].vertices[0];
      if (faceOfABound(u, v) <= best.gap) continue;
      const Candidate c = faceOfA(u, v, hint_b_);
      hint_b_ = w_.support_b[f] = c.ib;
      consider(c, best);
    }
    int hint_a = s.ia;
    for (std::size_t f = 0; f < faces_b.size(); ++f) {
      const Vec3& u = w_.normals_b[f];
      const int v = faces_b[f].vertices[0];
      if (faceOfBBound(u, v) <= best.gap) continue;
      const Candidate c = faceOfB(u, v, hint_a);
      hint_a = c.ia;
      consider(c, best);
    }
    const auto& edges_a = a_.shape->edges();
    for (std::size_t e = 0; e < edges_a.size(); ++e) {
      const geometry::Edge& edge = edges_a[e];
      if (edgeOfABound(w_.normals_a[edge.f0], w_.normals_a[edge.f1], edge.v0) <= best.gap) {
        continue;
      }
      walkArc(static_cast<int>(e), best);
    }
    return best;
  }

 private:
  // Upper bounds on the gap of candidates, from the inscribed balls (see bestOverall): a face of
  // A with outward normal u through vertex v, a face of B, an edge of A or B with face normals
  // u0, u1 through vertex v (all its Minkowski-face normals).
  double faceOfABound(const Vec3& u, int v) const { return -(u.dot(a_.vertices[v] - cb_) + rb_); }
  double faceOfBBound(const Vec3& u, int v) const { return -(u.dot(b_.vertices[v] - ca_) + ra_); }
  double edgeOfABound(const Vec3& u0, const Vec3& u1, int v) const {
    return maxOverArc(u0, u1, cb_ - a_.vertices[v]) - rb_;
  }
  double edgeOfBBound(const Vec3& u0, const Vec3& u1, int v) const {
    return maxOverArc(u0, u1, ca_ - b_.vertices[v]) - ra_;
  }

  void consider(const Candidate& c, Candidate& best) {
    ++trace_.candidates;
    if (c.gap > best.gap) best = c;
  }

  /// Normal -u of a face of A (u outward, world; v a vertex of it): min_A is on the face, max_B
  /// climbs.
  Candidate faceOfA(const Vec3& u, int v, int hint_b) const {
    const Extreme top_a = climbMax(a_, u, v), top_b = climbMax(b_, -u, hint_b);
    return {-u, -top_a.value - top_b.value, top_a.index, top_b.index};
  }

  /// Normal u of a face of B: max_B is on the face, min_A climbs.
  Candidate faceOfB(const Vec3& u, int v, int hint_a) const {
    const Extreme top_b = climbMax(b_, u, v), low_a = climbMax(a_, -u, hint_a);
    return {u, -low_a.value - top_b.value, low_a.index, top_b.index};
  }

  static void gatherFeatures(const Body& body, std::span<const int> band,
                             std::vector<std::pair<int, int>>& faces, std::vector<int>& edges) {
    faces.clear();
    edges.clear();
    for (int v : band) {
      for (int f : body.shape->vertexFaces()[v]) {
        const bool seen =
            std::any_of(faces.begin(), faces.end(), [f](const auto& p) { return p.first == f; });
        if (!seen) faces.emplace_back(f, v);
      }
      for (int e : body.shape->vertexEdges()[v]) {
        if (std::find(edges.begin(), edges.end(), e) == edges.end()) edges.push_back(e);
      }
    }
  }

  /// The band's edge (two vertices) or, for one vertex, its edge most nearly perpendicular to n.
  static int flattestEdge(const Body& body, std::span<const int> band, const Vec3& n) {
    if (band.size() == 2) return fcp_detail::edgeBetween(body, band[0], band[1]);
    const auto& neighbours = body.shape->vertexNeighbours()[band[0]];
    const Vec3& v = body.vertices[band[0]];
    std::size_t best = 0;
    double flattest = 2.0;
    for (std::size_t k = 0; k < neighbours.size(); ++k) {
      const Vec3 e = body.vertices[neighbours[k]] - v;
      const double slope = std::abs(e.dot(n)) / e.norm();
      if (slope < flattest) {
        flattest = slope;
        best = k;
      }
    }
    return body.shape->vertexEdges()[band[0]][best];
  }

  /// The face at the band's vertices whose outward normal is closest to d, and a vertex of it.
  static std::pair<int, int> squarestFace(const Body& body, std::span<const int> band,
                                          const Vec3& d) {
    const Vec3 local = body.rotation.transpose() * d;
    const auto& faces = body.shape->faces();
    std::pair<int, int> best{body.shape->vertexFaces()[band[0]][0], band[0]};
    double top = -2.0;
    for (int v : band) {
      for (int f : body.shape->vertexFaces()[v]) {
        const double c = local.dot(faces[f].normal);
        if (c > top) {
          top = c;
          best = {f, v};
        }
      }
    }
    return best;
  }

  /// B's support along the inward normal of face f of A (climbed once, from the last one).
  int supportOfFaceOfA(int f) {
    if (w_.support_b[f] < 0) w_.support_b[f] = climbMax(b_, -w_.normals_a[f], hint_b_).index;
    return w_.support_b[f];
  }

  /// The edges of B crossed by the normal arc of edge e of A, as candidates. Along the arc
  /// m(t) ~ (1 - t) m0 + t m1 (m0, m1 the inward normals of e's faces), B's support moves from
  /// vertex b to a neighbour b' where m(t).(b' - b) turns positive; the earliest such crossing
  /// is the next edge of B on the way.
  void walkArc(int e, Candidate& best) {
    const geometry::Edge& edge = a_.shape->edges()[e];
    const Vec3 m0 = -w_.normals_a[edge.f0], m1 = -w_.normals_a[edge.f1];
    const Vec3 dir_a = a_.vertices[edge.v1] - a_.vertices[edge.v0];
    const Vec3& point_a = a_.vertices[edge.v0];
    const auto& neighbours = b_.shape->vertexNeighbours();
    const int limit = static_cast<int>(b_.vertices.size());
    int b = supportOfFaceOfA(edge.f0);
    for (int step = 0; step <= limit; ++step) {
      int next = -1;
      double first = 2.0, rise = 0.0;
      const auto& around = neighbours[b];
      for (std::size_t k = 0; k < around.size(); ++k) {
        const Vec3 d = b_.vertices[around[k]] - b_.vertices[b];
        const double x0 = m0.dot(d), x1 = m1.dot(d);
        if (!(x1 > 0.0 && x1 > x0)) continue;  // never overtakes b before the arc's end
        const double t = x0 / (x0 - x1);
        if (t < first || (t == first && x1 > rise)) {
          first = t;
          rise = x1;
          next = around[k];
        }
      }
      if (next < 0) return;
      const Vec3 dir_b = b_.vertices[next] - b_.vertices[b];
      const Vec3 c = dir_a.cross(dir_b);
      const double norm2 = c.squaredNorm();
      const double parallel = kFcpParallelSine * dir_a.norm() * dir_b.norm();
      if (norm2 > parallel * parallel) {
        const Vec3 m = (c.dot(m0 + m1) >= 0.0 ? 1.0 : -1.0) / std::sqrt(norm2) * c;
        consider({m, m.dot(point_a - b_.vertices[b]), edge.v0, b}, best);
      }
      b = next;
      hint_b_ = b;
    }
    // A walk this long only happens on degenerate ties: test the edge against every edge of B.
    w_.cones_a.assign(1, edgeCone(a_, e));
    w_.cones_b.clear();
    for (std::size_t k = 0; k < b_.shape->edges().size(); ++k) {
      w_.cones_b.push_back(edgeCone(b_, static_cast<int>(k)));
    }
    edgePairs(best);
  }

  /// Edge pairs (A, B) whose cross product is a face normal of D = B - A: oriented c must lie in
  /// B's edge cone and -c in A's. Then B's support along c is its edge and A's along -c is its
  /// edge, and the gap is c.(a - b) for any points a, b of the edges (no support query).
  void edgePairs(Candidate& best) {
    for (const EdgeCone& ea : w_.cones_a) {
      for (const EdgeCone& eb : w_.cones_b) {
        const Vec3 c = ea.dir.cross(eb.dir);
        const double norm2 = c.squaredNorm();
        const double parallel = kFcpParallelSine * ea.length * eb.length;
        if (norm2 <= parallel * parallel) continue;
        const int side_b = coneSide(eb, c, norm2);
        if (side_b == 0 || coneSide(ea, c, norm2) != -side_b) continue;
        const Vec3 m = (side_b / std::sqrt(norm2)) * c;
        consider({m, m.dot(ea.point - eb.point), ea.v0, eb.v0}, best);
      }
    }
  }

  const Body& a_;
  const Body& b_;
  FcpTrace& trace_;
  SearchScratch& w_;
  double band_ = 0.0, improve_ = 0.0, slack_ = 0.0;
  int hint_b_ = 0;  // the last support of B found by the full scan
  Vec3 ca_, cb_;    // world incentres
  double ra_ = 0.0, rb_ = 0.0;
};

CommonPlane result(const Plane& s, bool separated_early) {
  CommonPlane cp;
  cp.normal = s.n;
  cp.gap = s.gap();
  cp.level_a = s.level_a;
  cp.level_b = s.level_b;
  cp.vertex_a = s.ia;
  cp.vertex_b = s.ib;
  cp.separated_early = separated_early;
  return cp;
}

}  // namespace

CommonPlane findCommonPlane(const Body& a, const Body& b, const Vec3* warm_normal,
                            const FcpOptions& options, FcpTrace* trace) {
  FcpTrace local_trace;
  FcpTrace& t = trace != nullptr ? *trace : local_trace;
  t = FcpTrace{};
  const double scale = fcp_detail::lengthScale(a, b);
  Vec3 n = Vec3::UnitZ();
  if (warm_normal != nullptr && warm_normal->squaredNorm() > 0.25) {
    n = warm_normal->normalized();
    t.warm = true;
  } else {
    // Perpendicular to the line joining the centroids (coincident centroids: any plane).
    const Vec3 d = a.centroid() - b.centroid();
    const double length = d.norm();
    if (length > FcpTolerance::kImprove * scale) n = d / length;
  }
  FcpSearch search(a, b, t);
  Plane s = search.start(n);
  if (options.stop_when_separated && s.gap() > 0.0) return result(s, true);
  search.settle(s);
  // Guess the plane of the features the start plane rests on (after a warm start, the last
  // step's plane moved with the bodies): the certificate accepts it without a search.
  s = search.fromCandidate(search.bestNatural(s));
  ++t.moves;
  if (options.stop_when_separated && s.gap() > 0.0) return result(s, true);
  bool tried = s.gap() <= 0.0;
  if (tried && search.certify(s)) {
    t.certified = true;
    return result(s, false);
  }
  // Local search: move to the best candidate at the closest vertices while it improves. Skipped
  // when the inscribed balls overlap (a deep overlap): the certificate's pieces cannot prove such
  // an optimum, and the exact scan costs about as much as a few local moves.
  const bool deep = !options.always_search && search.ballsOverlap();
  bool converged = false;
  for (int move = 0; move < (deep ? 0 : kMaxMoves); ++move) {
    const Candidate c = search.bestLocal(s);
    if (!search.improves(c, s)) {
      converged = true;
      break;
    }
    s = search.fromCandidate(c);
    ++t.moves;
    if (options.stop_when_separated && s.gap() > 0.0) return result(s, true);
    // The certificate is cheaper than confirming a local optimum with another round of candidates.
    tried = s.gap() <= 0.0;
    if (tried && search.certify(s)) {
      t.certified = true;
      return result(s, false);
    }
  }
  if (converged && !tried && s.gap() <= 0.0 && search.certify(s)) {
    t.certified = true;
    return result(s, false);
  }
  t.full_scan = true;
  const Candidate c = search.bestOverall(s);
  if (search.improves(c, s)) {
    s = search.fromCandidate(c);
    t.full_scan_improved = true;
  }
  return result(s, false);
}

}  // namespace polydem::contact
