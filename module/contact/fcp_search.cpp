// The FCP search (Nezami et al. 2004): local moves between candidate common planes, a certificate
// of global optimality, and a scan of every candidate when the certificate fails.
//
// With D = B - A (Minkowski difference), gap(n) = min_A n.a - max_B n.b = -h_D(n). The candidates
// that matter are the face normals of D: faces of A (normal -u, u outward), faces of B (normal u)
// and the pairs of an edge of A and an edge of B whose arcs on the Gauss sphere cross (Minkowski
// faces). At a plane n the vertex of D supporting n is (closest vertices of B) - (closest of A);
// the faces of D around it are built from the faces and edges at those vertices, and one of them
// is at least as good as n (n lies in their normal cone). A move to the best one strictly raises
// the gap, so the walk ends, at a local maximum of the gap. For separated pairs any positive gap
// proves separation. For overlapping pairs the local maximum need not be global (one per face of
// D whose foot point lies inside it); fcp_certificate.cpp proves it global or the full scan runs.
#include <algorithm>
#include <cmath>
#include <limits>

#include "contact/fcp.h"
#include "contact/fcp_detail.h"

namespace polydem::contact {

namespace {

using fcp_detail::climbMax;
using fcp_detail::collectBand;
using fcp_detail::Extreme;

/// Local moves before the full scan takes over (a cold start on 40-vertex bodies needs < 10).
constexpr int kMaxMoves = 64;
/// Slack of the normal-cone test, as a sine: arcs touching at an end still count as crossing.
constexpr double kConeSlack = 1e-12;

/// An edge of a placed body prepared for the Minkowski-face test. A direction c lies in the cone
/// of outward normals of the edge, {s u0 + t u1 : s, t >= 0}, iff c.p >= 0 and c.q >= 0 with
/// w = u0 x u1, p = u1 x w, q = w x u0 (c = s u0 + t u1 gives c x u1 = s w, u0 x c = t w).
struct EdgeCone {
  Vec3 dir, point, p, q;
  double scale = 0.0;  // |w|, the sine of the angle between the faces' normals
  int v0 = 0;
};

EdgeCone edgeCone(const Body& body, int e) {
  const geometry::Edge& edge = body.shape->edges()[e];
  const Vec3 u0 = body.faceNormal(edge.f0), u1 = body.faceNormal(edge.f1);
  const Vec3 w = u0.cross(u1);
  return {body.vertices[edge.v1] - body.vertices[edge.v0],
          body.vertices[edge.v0],
          u1.cross(w),
          w.cross(u0),
          w.norm(),
          edge.v0};
}

/// +1 if c lies in the edge's normal cone, -1 if -c does, 0 if neither.
int coneSide(const EdgeCone& e, const Vec3& c, double c_norm) {
  const double tol = kConeSlack * c_norm * e.scale;
  const double s = c.dot(e.p), t = c.dot(e.q);
  if (s >= -tol && t >= -tol) return 1;
  if (s <= tol && t <= tol) return -1;
  return 0;
}

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

struct Scratch {
  std::vector<int> band_a, band_b, edges_a, edges_b;
  std::vector<std::pair<int, int>> faces_a, faces_b;  // (face, a vertex of it)
  std::vector<EdgeCone> cones_a, cones_b;
};

/// Per-thread buffers (polydem runs one thread per rank): no allocation once they have grown.
Scratch& scratch() {
  thread_local Scratch s;
  return s;
}

class Search {
 public:
  Search(const Body& a, const Body& b, FcpTrace& trace)
      : a_(a), b_(b), trace_(trace), w_(scratch()) {
    const double scale = fcp_detail::lengthScale(a, b);
    band_ = FcpTolerance::kBand * scale;
    improve_ = FcpTolerance::kImprove * scale;
    slack_ = FcpTolerance::kCertify * scale;
  }

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
    Candidate best;
    for (const auto& [f, v] : w_.faces_a) consider(faceOfA(f, v, s.ib), best);
    for (const auto& [f, v] : w_.faces_b) consider(faceOfB(f, v, s.ia), best);
    prepareCones(a_, w_.edges_a, w_.cones_a);
    prepareCones(b_, w_.edges_b, w_.cones_b);
    edgePairs(best);
    return best;
  }

  /// Best candidate of all: every face of A and B and every Minkowski-face edge pair.
  Candidate bestOverall(const Plane& s) {
    Candidate best;
    const int nfa = static_cast<int>(a_.shape->faces().size());
    const int nfb = static_cast<int>(b_.shape->faces().size());
    int hint_a = s.ia, hint_b = s.ib;
    for (int f = 0; f < nfa; ++f) {
      const Candidate c = faceOfA(f, a_.shape->faces()[f].vertices[0], hint_b);
      hint_b = c.ib;
      consider(c, best);
    }
    for (int f = 0; f < nfb; ++f) {
      const Candidate c = faceOfB(f, b_.shape->faces()[f].vertices[0], hint_a);
      hint_a = c.ia;
      consider(c, best);
    }
    allEdges(a_, w_.edges_a);
    allEdges(b_, w_.edges_b);
    prepareCones(a_, w_.edges_a, w_.cones_a);
    prepareCones(b_, w_.edges_b, w_.cones_b);
    edgePairs(best);
    return best;
  }

  std::span<const int> bandA() const { return w_.band_a; }
  std::span<const int> bandB() const { return w_.band_b; }

 private:
  void consider(const Candidate& c, Candidate& best) {
    ++trace_.candidates;
    if (c.gap > best.gap) best = c;
  }

  /// Normal -u of face f of A (u outward; v a vertex of f): min_A is on the face, max_B climbs.
  Candidate faceOfA(int f, int v, int hint_b) const {
    const Vec3 u = a_.faceNormal(f);
    const Extreme top_a = climbMax(a_, u, v), top_b = climbMax(b_, -u, hint_b);
    return {-u, -top_a.value - top_b.value, top_a.index, top_b.index};
  }

  /// Normal u of face f of B: max_B is on the face, min_A climbs.
  Candidate faceOfB(int f, int v, int hint_a) const {
    const Vec3 u = b_.faceNormal(f);
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

  static void allEdges(const Body& body, std::vector<int>& edges) {
    edges.resize(body.shape->edges().size());
    for (std::size_t e = 0; e < edges.size(); ++e) edges[e] = static_cast<int>(e);
  }

  static void prepareCones(const Body& body, std::span<const int> edges,
                           std::vector<EdgeCone>& cones) {
    cones.clear();
    for (int e : edges) cones.push_back(edgeCone(body, e));
  }

  /// Edge pairs (A, B) whose cross product is a face normal of D = B - A: oriented c must lie in
  /// B's edge cone and -c in A's. Then B's support along c is its edge and A's along -c is its
  /// edge, and the gap is c.(a - b) for any points a, b of the edges (no support query).
  void edgePairs(Candidate& best) {
    for (const EdgeCone& ea : w_.cones_a) {
      const double la = ea.dir.norm();
      for (const EdgeCone& eb : w_.cones_b) {
        const Vec3 c = ea.dir.cross(eb.dir);
        const double norm = c.norm();
        if (norm <= kFcpParallelSine * la * eb.dir.norm()) continue;
        const int side_b = coneSide(eb, c, norm);
        if (side_b == 0 || coneSide(ea, c, norm) != -side_b) continue;
        const Vec3 m = (side_b / norm) * c;
        consider({m, m.dot(ea.point - eb.point), ea.v0, eb.v0}, best);
      }
    }
  }

  const Body& a_;
  const Body& b_;
  FcpTrace& trace_;
  Scratch& w_;
  double band_ = 0.0, improve_ = 0.0, slack_ = 0.0;
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
  Search search(a, b, t);
  Plane s = search.start(n);
  if (options.stop_when_separated && s.gap() > 0.0) return result(s, true);
  search.settle(s);
  bool converged = false;
  for (int move = 0; move < kMaxMoves; ++move) {
    const Candidate c = search.bestLocal(s);
    // The first move always goes to a candidate, so that the normal is a face or edge-pair normal
    // and not the start direction; later ones only when they improve.
    if (move > 0 && !search.improves(c, s)) {
      converged = true;
      break;
    }
    s = search.fromCandidate(c);
    ++t.moves;
    if (options.stop_when_separated && s.gap() > 0.0) return result(s, true);
    // A warm start is usually one move from the answer: try the certificate before confirming.
    if (move == 0 && t.warm && s.gap() <= 0.0 && search.certify(s)) {
      t.certified = true;
      return result(s, false);
    }
  }
  if (converged && s.gap() <= 0.0 && search.certify(s)) {
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
