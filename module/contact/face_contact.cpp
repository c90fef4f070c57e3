#include "polydem/contact/face_contact.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "polydem/contact/support.h"
#include "polydem/core/tolerance.h"
#include "polydem/geometry/polygon.h"

namespace polydem::contact {

namespace {

const double kCosFacing = std::cos(kFacingAngleDeg * std::numbers::pi / 180.0);
const double kSinFacing = std::sin(kFacingAngleDeg * std::numbers::pi / 180.0);

// Among the faces around vertex `support`, the one whose world outward normal is closest to
// `direction` and within the facing angle of it; -1 if none. Ties go to the first in the vertex's
// face order, which depends only on the shape.
int facingFace(const Body& body, const Vec3& direction, int support) {
  int best = -1;
  double best_cos = kCosFacing;
  for (int f : body.shape->vertexFaces()[support]) {
    const double c = body.faceNormal(f).dot(direction);
    if (c > best_cos) best = f, best_cos = c;
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

void FaceContactBuilder::project(const Body& body, int face, std::vector<Vec2>& corners,
                                 std::vector<int>& vertex, std::vector<int>& edge) const {
  const auto& f = body.shape->faces()[face];
  const int m = static_cast<int>(f.vertices.size());
  corners.resize(m);
  vertex.resize(m);
  edge.resize(m);
  double twice_area = 0.0;
  for (int i = 0; i < m; ++i) {
    const Vec3 d = body.vertices[f.vertices[i]] - frame_.origin;
    corners[i] = Vec2(frame_.u.dot(d), frame_.v.dot(d));
  }
  for (int i = 0; i < m; ++i)
    twice_area += geometry::cross2(corners[i], corners[i + 1 < m ? i + 1 : 0]);
  if (twice_area >= 0.0) {  // counter-clockwise seen from +n already (B's face)
    for (int i = 0; i < m; ++i) vertex[i] = f.vertices[i], edge[i] = f.edges[i];
    return;
  }
  // A face seen from its back (A's face looks along -n): reverse it. Edge i of the reversed
  // polygon joins reversed corners i and i + 1, i.e. the original edge m - 2 - i (mod m).
  std::reverse(corners.begin(), corners.end());
  for (int i = 0; i < m; ++i) {
    vertex[i] = f.vertices[m - 1 - i];
    edge[i] = f.edges[m - 2 - i >= 0 ? m - 2 - i : m - 1];  // i = m - 1: edge m - 1
  }
}

SubContact FaceContactBuilder::fromCorner(const Body& a, const Body& b, const LabelledCorner& k,
                                          const Vec3& n) const {
  SubContact s;
  s.feature = featureKey(k.a, k.b);
  const FeatureType ta = featureType(k.a), tb = featureType(k.b);
  if (ta == FeatureType::kVertex) {  // A's vertex inside B's face: pushed out along B's normal
    const auto& face = b.shape->faces()[featureIndex(k.b)];
    const Vec3 nb = b.faceNormal(featureIndex(k.b));
    const Vec3& x = a.vertices[featureIndex(k.a)];
    s.normal = nb;
    s.gap = nb.dot(b.vertices[face.vertices[0]] - x);
    s.point = x + (0.5 * s.gap) * nb;
  } else if (tb == FeatureType::kVertex) {  // B's vertex inside A's face
    const auto& face = a.shape->faces()[featureIndex(k.a)];
    const Vec3 na = a.faceNormal(featureIndex(k.a));
    const Vec3& x = b.vertices[featureIndex(k.b)];
    s.normal = -na;
    s.gap = na.dot(a.vertices[face.vertices[0]] - x);
    s.point = x + (0.5 * s.gap) * na;
  } else {  // crossing edges: the points of each edge above and below the projected crossing
    const auto& ea = a.shape->edges()[featureIndex(k.a)];
    const auto& eb = b.shape->edges()[featureIndex(k.b)];
    auto lift = [&](const Body& body, int v0, int v1) {
      const Vec3& x0 = body.vertices[v0];
      const Vec3& x1 = body.vertices[v1];
      auto flat = [&](const Vec3& x) {
        const Vec3 d = x - frame_.origin;
        return Vec2(frame_.u.dot(d), frame_.v.dot(d));
      };
      return Vec3(x0 + along(k.p, flat(x0), flat(x1)) * (x1 - x0));
    };
    const Vec3 pa = lift(a, ea.v0, ea.v1), pb = lift(b, eb.v0, eb.v1);
    s.normal = n;
    s.gap = n.dot(pb - pa);
    s.point = 0.5 * (pa + pb);
  }
  return s;
}

bool FaceContactBuilder::faceFace(const Body& a, const Body& b, int fa, int fb, const Contact& c) {
  project(a, fa, corners_a_, vertex_a_, edge_a_);
  project(b, fb, corners_b_, vertex_b_, edge_b_);
  clipper_.polygons({corners_a_, vertex_a_, edge_a_, fa}, {corners_b_, vertex_b_, edge_b_, fb},
                    RelTol::kPoint * scale_, overlap_);
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
  double twice_area = 0.0, extent = 0.0;
  shares_.resize(m);
  for (int i = 0; i < m; ++i) {
    const Vec2& p = overlap_[i].p;
    const Vec2& q = overlap_[i + 1 < m ? i + 1 : 0].p;
    shares_[i] = std::max(0.5 * geometry::cross2(p - middle, q - middle), 0.0);
    twice_area += 2.0 * shares_[i];
    extent = std::max(extent, (p - q).norm());
  }
  if (!(twice_area > 2.0 * RelTol::kIteration * scale_ * extent)) return false;
  subs_.clear();
  for (int i = 0; i < m; ++i) {
    SubContact s = fromCorner(a, b, overlap_[i], c.normal);
    s.weight = 0.5 * (shares_[i] + shares_[i > 0 ? i - 1 : m - 1]) / (0.5 * twice_area);
    subs_.push_back(s);
  }
  area_ = 0.5 * twice_area;
  return true;
}

bool FaceContactBuilder::edgeFace(const Body& edge_body, const Body& face_body, int edge, int face,
                                  bool edge_is_a, const Contact& c) {
  project(face_body, face, corners_b_, vertex_b_, edge_b_);
  const auto& e = edge_body.shape->edges()[edge];
  auto flat = [&](int v) {
    const Vec3 d = edge_body.vertices[v] - frame_.origin;
    return Vec2(frame_.u.dot(d), frame_.v.dot(d));
  };
  const Vec2 s0 = flat(e.v0), s1 = flat(e.v1);
  clipper_.segment(s0, s1, e.v0, e.v1, edge, edge_is_a, {corners_b_, vertex_b_, edge_b_, face},
                   overlap_);
  if (overlap_.size() != 2) return false;
  if (!((overlap_[1].p - overlap_[0].p).norm() > RelTol::kPoint * scale_)) return false;
  const Body& a = edge_is_a ? edge_body : face_body;
  const Body& b = edge_is_a ? face_body : edge_body;
  subs_.clear();
  for (const auto& k : overlap_) {
    SubContact s = fromCorner(a, b, k, c.normal);
    s.weight = 0.5;
    subs_.push_back(s);
  }
  return true;
}

void FaceContactBuilder::finish() {
  // Canonical order, and one sub-contact per feature pair: a degenerate clip (a corner exactly on
  // an edge line) can meet the same pair of features twice; their weights are merged.
  // A pair has a handful of corners: a stable insertion sort, the order std::sort gives to
  // ranges this short (it insertion-sorts up to 16 elements), without the call.
  const auto before = [](const SubContact& x, const SubContact& y) {
    return x.feature < y.feature;
  };
  if (subs_.size() > 16) {
    std::sort(subs_.begin(), subs_.end(), before);
  } else {
    for (std::size_t i = 1; i < subs_.size(); ++i) {
      const SubContact s = subs_[i];
      std::size_t j = i;
      for (; j > 0 && before(s, subs_[j - 1]); --j) subs_[j] = subs_[j - 1];
      subs_[j] = s;
    }
  }
  std::size_t kept = 0;
  for (std::size_t i = 0; i < subs_.size(); ++i) {
    if (kept > 0 && subs_[kept - 1].feature == subs_[i].feature) {
      subs_[kept - 1].weight += subs_[i].weight;
    } else {
      subs_[kept++] = subs_[i];
    }
  }
  subs_.resize(kept);
}

FaceContact FaceContactBuilder::build(const Body& a, const Body& b, const Contact& c) {
  const Vec3& n = c.normal;
  scale_ = pairLengthScale(a, b);
  area_ = 0.0;
  const Vec3 u = (std::abs(n.x()) < 0.6 ? Vec3::UnitX() : Vec3::UnitY()).cross(n).normalized();
  frame_ = {c.point, u, n.cross(u)};
  const int ia = supportIndex(a, -n), ib = supportIndex(b, n);
  const int fa = facingFace(a, -n, ia), fb = facingFace(b, n, ib);
  ContactArea kind = ContactArea::kPoint;
  if (fa >= 0 && fb >= 0) {
    if (faceFace(a, b, fa, fb, c)) kind = ContactArea::kFace;
  } else if (fb >= 0) {
    const int ea = flatEdge(a, n, ia);
    if (ea >= 0 && edgeFace(a, b, ea, fb, true, c)) kind = ContactArea::kLine;
  } else if (fa >= 0) {
    const int eb = flatEdge(b, n, ib);
    if (eb >= 0 && edgeFace(b, a, eb, fa, false, c)) kind = ContactArea::kLine;
  }
  if (kind != ContactArea::kPoint) {
    finish();
    // A penetrating pair whose chosen features are all apart (a corner of one body in the
    // other's edge region): the kernel's point is the better answer.
    const bool any =
        std::any_of(subs_.begin(), subs_.end(), [](const SubContact& s) { return s.gap > 0.0; });
    if (!any && c.depth > 0.0) kind = ContactArea::kPoint;
  }
  if (kind == ContactArea::kPoint) {
    subs_.assign(1, SubContact{0, c.point, n, c.depth, 1.0});
    area_ = 0.0;
  }
  return {kind, area_, subs_};
}

}  // namespace polydem::contact
