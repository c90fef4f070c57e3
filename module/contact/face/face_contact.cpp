#include "polydem/contact/face/face_contact.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "polydem/contact/support.h"
#include "polydem/core/tolerance.h"
#include "polydem/geometry/polygon.h"

namespace polydem::contact {

namespace {

const double kSinFacing = std::sin(kFacingAngleDeg * std::numbers::pi / 180.0);

// Among the faces around vertex `support`, the one whose world outward normal is closest to
// `direction` and within the facing angle of it; -1 if none. Ties go to the first in the vertex's
// face order, which depends only on the shape. `normal` gets the chosen face's world normal.
int facingFace(const Body& body, const Vec3& direction, int support, Vec3& normal) {
  int best = -1;
  double best_cos = kCosFacing;
  for (int f : body.shape->vertexFaces()[support]) {
    const Vec3 nf = body.faceNormal(f);
    const double c = nf.dot(direction);
    if (c > best_cos) best = f, best_cos = c, normal = nf;
  }
  return best;
}

// Among the edges at vertex `support`, the one closest to parallel to the plane normal to `n` and
// within the facing angle of it; -1 if none.
int flatEdge(const Body& body, const Vec3& n, int support) {
  int best = -1;
  double best_sin = kSinFacing;
  for (int e : body.shape->vertexEdges()[support]) {
    const auto& edge = body.shape->edges()[e];
    const Vec3 d = body.vertices[edge.v1] - body.vertices[edge.v0];
    const double s = std::abs(d.dot(n)) / d.norm();
    if (s < best_sin) best = e, best_sin = s;
  }
  return best;
}

// Position of `x` along the projected segment p0 -> p1 (0 at p0, 1 at p1).
double along(const Vec2& x, const Vec2& p0, const Vec2& p1) {
  const Vec2 d = p1 - p0;
  return (x - p0).dot(d) / d.squaredNorm();
}

}  // namespace

FaceContactBuilder::Facing FaceContactBuilder::facingSide(const Body& body, const Vec3& direction,
                                                          int support) {
  Facing f;
  f.face = facingFace(body, direction, support, f.normal);
  if (f.face >= 0) f.base = &body.vertices[body.shape->faces()[f.face].vertices[0]];
  return f;
}

LabelledPolygon FaceContactBuilder::project(const Body& body, int face, bool seen_from_back,
                                            std::vector<Vec2>& corners, std::vector<int>& vertex,
                                            std::vector<int>& edge) const {
  const auto& f = body.shape->faces()[face];
  const int m = static_cast<int>(f.vertices.size());
  const int* ids = f.vertices.data();
  corners.resize(m);
  Vec2* out = corners.data();
  if (!seen_from_back) {  // counter-clockwise seen from +n already (B's face): the face's lists
    for (int i = 0; i < m; ++i) out[i] = flat(body.vertices[ids[i]]);
    return {corners, f.vertices, f.edges, face};
  }
  // A face seen from its back (A's face looks along -n): reversed. Edge i of the reversed
  // polygon joins reversed corners i and i + 1, i.e. the original edge m - 2 - i (mod m).
  vertex.resize(m);
  edge.resize(m);
  for (int i = 0; i < m; ++i) {
    vertex[i] = ids[m - 1 - i];
    out[i] = flat(body.vertices[vertex[i]]);
    edge[i] = f.edges[m - 2 - i >= 0 ? m - 2 - i : m - 1];  // i = m - 1: edge m - 1
  }
  return {corners, vertex, edge, face};
}

inline void FaceContactBuilder::fromCorner(const Body& a, const Body& b, const LabelledCorner& k,
                                           const Vec3& n, double weight, SubContact& s) const {
  s.weight = weight;
  s.feature = featureKey(k.a, k.b);
  const FeatureType ta = featureType(k.a), tb = featureType(k.b);
  // A vertex of one body lies inside the other's face, which is that body's facing face (the
  // only face the clip labels): its normal and first vertex were kept by build().
  if (ta == FeatureType::kVertex) {  // A's vertex inside B's face: pushed out along B's normal
    const Vec3& nb = facing_b_.normal;
    const Vec3& x = a.vertices[featureIndex(k.a)];
    s.normal = nb;
    s.gap = nb.dot(*facing_b_.base - x);
    s.point = x + (0.5 * s.gap) * nb;
  } else if (tb == FeatureType::kVertex) {  // B's vertex inside A's face
    const Vec3& na = facing_a_.normal;
    const Vec3& x = b.vertices[featureIndex(k.b)];
    s.normal = -na;
    s.gap = na.dot(*facing_a_.base - x);
    s.point = x + (0.5 * s.gap) * na;
  } else {  // crossing edges: the points of each edge above and below the projected crossing
    const Vec3 pa = lift(a, featureIndex(k.a), k.side_a, polygon_a_, k.p);
    const Vec3 pb = lift(b, featureIndex(k.b), k.side_b, polygon_b_, k.p);
    s.normal = n;
    s.gap = n.dot(pb - pa);
    s.point = 0.5 * (pa + pb);
  }
}

inline Vec3 FaceContactBuilder::lift(const Body& body, int e, int side,
                                     const LabelledPolygon& polygon, const Vec2& p) const {
  const auto& edge = body.shape->edges()[e];
  const Vec3& x0 = body.vertices[edge.v0];
  const Vec3& x1 = body.vertices[edge.v1];
  if (side < 0) return x0 + along(p, flat(x0), flat(x1)) * (x1 - x0);
  // The edge's ends as project() placed them: the same values as projecting them again.
  const int m = static_cast<int>(polygon.corners.size());
  const int next = side + 1 < m ? side + 1 : 0;
  const bool forward = polygon.vertex[side] == edge.v0;
  const Vec2& p0 = polygon.corners[forward ? side : next];
  const Vec2& p1 = polygon.corners[forward ? next : side];
  return x0 + along(p, p0, p1) * (x1 - x0);
}

bool FaceContactBuilder::faceFace(const Body& a, const Body& b, const Contact& c) {
  const int fa = facing_a_.face, fb = facing_b_.face;
  polygon_a_ = project(a, fa, true, corners_a_, vertex_a_, edge_a_);
  polygon_b_ = project(b, fb, false, corners_b_, vertex_b_, edge_b_);
  clipper_.polygons(polygon_a_, polygon_b_, RelTol::kPoint * scale_, overlap_);
  const int m = static_cast<int>(overlap_.size());
  if (m < 3) return false;
  // Each corner's share of the area: half of the two fan triangles (middle, corner, neighbour)
  // it belongs to, the middle being the mean of the corners. That is inside a convex polygon, so
  // no share is negative even for a sliver whose area centroid is lost to round-off; for a
  // triangle every corner gets a third, for a parallelogram a quarter, so that a uniform gap puts
  // the resultant at the centroid of the area.
  Vec2 middle = Vec2::Zero();
  for (const auto& k : overlap_) middle += k.p;
  middle /= static_cast<double>(m);
  double twice_area = 0.0, extent2 = 0.0;
  shares_.resize(m);
  for (int i = 0; i < m; ++i) {
    const Vec2& p = overlap_[i].p;
    const Vec2& q = overlap_[i + 1 < m ? i + 1 : 0].p;
    shares_[i] = std::max(0.5 * geometry::cross2(p - middle, q - middle), 0.0);
    twice_area += 2.0 * shares_[i];
    extent2 = std::max(extent2, (p - q).squaredNorm());
  }
  // The longest side. One square root of the largest square is the largest of the roots: the
  // root is monotonic and correctly rounded.
  const double extent = std::sqrt(extent2);
  if (!(twice_area > 2.0 * RelTol::kIteration * scale_ * extent)) return false;
  // Corner i's weight: half its two triangles over the area. Written as a division per corner
  // (not one reciprocal for the pair), which rounds as the weights always have: the rock-slope
  // scenes' results depend on these bits.
  pending_.resize(m);
  for (int i = 0; i < m; ++i) {
    const double weight = 0.5 * (shares_[i] + shares_[i > 0 ? i - 1 : m - 1]) / (0.5 * twice_area);
    pending_[i] = {featureKey(overlap_[i].a, overlap_[i].b), weight, i};
  }
  area_ = 0.5 * twice_area;
  finish(a, b, c.normal);
  return true;
}

bool FaceContactBuilder::edgeFace(const Body& edge_body, const Body& face_body, int edge,
                                  bool edge_is_a, const Contact& c) {
  const int face = edge_is_a ? facing_b_.face : facing_a_.face;
  // A's face (seen from its back, so reversed) goes into A's buffers and B's into B's, as in
  // faceFace(): buffers that a face-face pair has grown already, so an edge-face pair meeting
  // later allocates nothing.
  const LabelledPolygon polygon =
      edge_is_a ? project(face_body, face, false, corners_b_, vertex_b_, edge_b_)
                : project(face_body, face, true, corners_a_, vertex_a_, edge_a_);
  const auto& e = edge_body.shape->edges()[edge];
  const Vec2 s0 = flat(edge_body.vertices[e.v0]), s1 = flat(edge_body.vertices[e.v1]);
  clipper_.segment(s0, s1, e.v0, e.v1, edge, edge_is_a, polygon, overlap_);
  if (overlap_.size() != 2) return false;
  if (!((overlap_[1].p - overlap_[0].p).norm() > RelTol::kPoint * scale_)) return false;
  pending_.resize(2);
  for (int i = 0; i < 2; ++i) pending_[i] = {featureKey(overlap_[i].a, overlap_[i].b), 0.5, i};
  finish(edge_is_a ? edge_body : face_body, edge_is_a ? face_body : edge_body, c.normal);
  return true;
}

void FaceContactBuilder::sortPending() {
  // Canonical order, and one sub-contact per feature pair: a degenerate clip (a corner exactly on
  // an edge line) can meet the same pair of features twice; their weights are merged, and only
  // the first of them becomes a sub-contact. The corners are sorted as small (feature, weight,
  // corner) entries before any sub-contact is made from them.
  // A pair has a handful of corners: a stable insertion sort, the order std::sort gives to
  // ranges this short (it insertion-sorts up to 16 elements), without the call; longer ones go
  // through std::sort, whose order depends only on the comparisons, as before.
  const auto before = [](const Pending& x, const Pending& y) { return x.feature < y.feature; };
  if (pending_.size() > 16) {
    std::sort(pending_.begin(), pending_.end(), before);
  } else {
    for (std::size_t i = 1; i < pending_.size(); ++i) {
      if (!before(pending_[i], pending_[i - 1])) continue;  // in place already: not moved
      const Pending p = pending_[i];
      std::size_t j = i;
      for (; j > 0 && before(p, pending_[j - 1]); --j) pending_[j] = pending_[j - 1];
      pending_[j] = p;
    }
  }
  std::size_t kept = 0;
  for (std::size_t i = 0; i < pending_.size(); ++i) {
    if (kept > 0 && pending_[kept - 1].feature == pending_[i].feature) {
      pending_[kept - 1].weight += pending_[i].weight;
    } else {
      if (kept != i) pending_[kept] = pending_[i];  // most clips merge nothing: no self-copies
      ++kept;
    }
  }
  pending_.resize(kept);
}

void FaceContactBuilder::finish(const Body& a, const Body& b, const Vec3& n) {
  sortPending();
  subs_.resize(pending_.size());
  for (std::size_t i = 0; i < pending_.size(); ++i) {
    fromCorner(a, b, overlap_[pending_[i].corner], n, pending_[i].weight, subs_[i]);
  }
}

FaceContact FaceContactBuilder::build(const Body& a, const Body& b, const Contact& c) {
  const Vec3& n = c.normal;
  scale_ = pairLengthScale(a, b);
  area_ = 0.0;
  ContactArea kind = ContactArea::kPoint;
  if (box_path_ && a.shape->box() && b.shape->box() && boxFaceFace(a, b, c, kind)) {
    return conclude(c, kind);
  }
  const Vec3 u = (std::abs(n.x()) < 0.6 ? Vec3::UnitX() : Vec3::UnitY()).cross(n).normalized();
  frame_ = {c.point, u, n.cross(u)};
  const int ia = supportIndex(a, -n), ib = supportIndex(b, n);
  facing_a_ = facingSide(a, -n, ia);
  facing_b_ = facingSide(b, n, ib);
  if (facing_a_.face >= 0 && facing_b_.face >= 0) {
    if (faceFace(a, b, c)) kind = ContactArea::kFace;
  } else if (facing_b_.face >= 0) {
    const int ea = flatEdge(a, n, ia);
    if (ea >= 0 && edgeFace(a, b, ea, true, c)) kind = ContactArea::kLine;
  } else if (facing_a_.face >= 0) {
    const int eb = flatEdge(b, n, ib);
    if (eb >= 0 && edgeFace(b, a, eb, false, c)) kind = ContactArea::kLine;
  }
  return conclude(c, kind);
}

FaceContact FaceContactBuilder::conclude(const Contact& c, ContactArea kind) {
  if (kind != ContactArea::kPoint) {
    // A penetrating pair whose chosen features are all apart (a corner of one body in the
    // other's edge region): the kernel's point is the better answer.
    const bool any =
        std::any_of(subs_.begin(), subs_.end(), [](const SubContact& s) { return s.gap > 0.0; });
    if (!any && c.depth > 0.0) kind = ContactArea::kPoint;
  }
  if (kind == ContactArea::kPoint) {
    subs_.assign(1, SubContact{0, c.point, c.normal, c.depth, 1.0});
    area_ = 0.0;
  }
  if (kind == ContactArea::kFace) return {kind, area_, subs_, facing_a_.face, facing_b_.face};
  return {kind, area_, subs_};
}

}  // namespace polydem::contact
