// The reference sub-contact builder, verbatim (face_contact_reference.h).
#include "face_contact_reference.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <utility>

#include "polydem/contact/support.h"
#include "polydem/core/tolerance.h"
#include "polydem/geometry/polygon.h"

namespace polydem::contact::reference {

namespace {

using geometry::cross2;

// The vertex of B where B's edge line `previous` (a line clipped by earlier) meets line `k`.
// Lines are clipped in order, so previous < k; the two are adjacent when k = previous + 1, or
// when they are the last and the first line. Non-adjacent lines meet outside B, and a corner
// there is cut away by a later line; it gets the start of line k as a placeholder label.
int sharedVertex(const LabelledPolygon& b, int previous, int k) {
  const int n = static_cast<int>(b.corners.size());
  if (previous == 0 && k == n - 1) return b.vertex[0];
  return b.vertex[k];
}

// Makes `buffer` hold at least `size` elements; it never shrinks, so once warm this allocates
// nothing.
template <typename T>
void grow(std::vector<T>& buffer, std::size_t size) {
  if (buffer.size() < size) buffer.resize(size);
}

}  // namespace

void ReferenceClipper::polygons(const LabelledPolygon& a, const LabelledPolygon& b, double merge,
                                std::vector<LabelledCorner>& out) {
  out.clear();
  const int na = static_cast<int>(a.corners.size()), nb = static_cast<int>(b.corners.size());
  // The working polygons live in buffers that only grow, indexed directly: a pass over n corners
  // writes at most 2 n (every edge keeps its start and adds at most one crossing), so each pass
  // makes room for that first and then writes without a capacity check per corner.
  grow(poly_, static_cast<std::size_t>(na));
  for (int i = 0; i < na; ++i) {
    poly_[i] = {{a.corners[i], feature(FeatureType::kVertex, a.vertex[i]),
                 feature(FeatureType::kFace, b.face)},
                a.edge[i]};
  }
  std::size_t n = static_cast<std::size_t>(na);
  for (int k = 0; k < nb && n > 0; ++k) {
    const Vec2& q0 = b.corners[k];
    const Vec2 d = b.corners[k + 1 < nb ? k + 1 : 0] - q0;
    if (d.squaredNorm() == 0.0) continue;  // a repeated corner carries no line
    grow(h_, n);
    const Working* poly = poly_.data();
    double* h = h_.data();
    bool any_out = false, any_in = false;
    for (std::size_t i = 0; i < n; ++i) {
      h[i] = cross2(d, poly[i].corner.p - q0);  // >= 0: left of the edge, inside B
      (h[i] < 0.0 ? any_out : any_in) = true;
    }
    if (!any_out) continue;
    if (!any_in) {
      n = 0;
      break;
    }
    grow(next_, 2 * n);
    Working* next = next_.data();
    std::size_t kept_count = 0;
    for (std::size_t i = 0; i < n; ++i) {
      const std::size_t j = i + 1 == n ? 0 : i + 1;
      const double hi = h[i], hj = h[j];
      const Working& wi = poly[i];
      if (hi >= 0.0) {
        Working& kept = next[kept_count++];
        kept = wi;
        if (hi == 0.0 && hj < 0.0) kept.carrier = -1 - k;  // leaves along the clip line
      }
      if (!((hi > 0.0 && hj < 0.0) || (hi < 0.0 && hj > 0.0))) continue;
      Working& x = next[kept_count++];
      x.corner.p = wi.corner.p + (hi / (hi - hj)) * (poly[j].corner.p - wi.corner.p);
      if (wi.carrier >= 0) {  // an edge of A crosses B's edge k
        x.corner.a = feature(FeatureType::kEdge, wi.carrier);
        x.corner.b = feature(FeatureType::kEdge, b.edge[k]);
      } else {  // two of B's edge lines meet: a vertex of B inside A's face
        x.corner.a = feature(FeatureType::kFace, a.face);
        x.corner.b = feature(FeatureType::kVertex, sharedVertex(b, -1 - wi.carrier, k));
      }
      // Entering, the polygon goes on along the crossed edge; leaving, along the clip line.
      x.carrier = hi < 0.0 ? wi.carrier : -1 - k;
    }
    std::swap(poly_, next_);
    n = kept_count;
  }
  const double merge2 = merge * merge;
  for (std::size_t i = 0; i < n; ++i) {
    const LabelledCorner& c = poly_[i].corner;
    if (!out.empty() && (c.p - out.back().p).squaredNorm() <= merge2) continue;
    out.push_back(c);
  }
  if (out.size() > 1 && (out.front().p - out.back().p).squaredNorm() <= merge2) out.pop_back();
}

void ReferenceClipper::segment(const Vec2& s0, const Vec2& s1, int v0, int v1, int edge,
                               bool segment_is_a, const LabelledPolygon& polygon,
                               std::vector<LabelledCorner>& out) {
  out.clear();
  const int n = static_cast<int>(polygon.corners.size());
  double t_lo = 0.0, t_hi = 1.0;
  int k_lo = -1, k_hi = -1;  // the polygon edge that cut each end (-1: the end is inside)
  for (int k = 0; k < n; ++k) {
    const Vec2& q0 = polygon.corners[k];
    const Vec2 d = polygon.corners[(k + 1) % n] - q0;
    if (d.squaredNorm() == 0.0) continue;
    const double h0 = cross2(d, s0 - q0), h1 = cross2(d, s1 - q0);  // >= 0 inside
    if (h0 < 0.0 && h1 < 0.0) return;
    if (h0 < 0.0) {
      const double t = h0 / (h0 - h1);
      if (t > t_lo) t_lo = t, k_lo = k;
    } else if (h1 < 0.0) {
      const double t = h0 / (h0 - h1);
      if (t < t_hi) t_hi = t, k_hi = k;
    }
  }
  if (!(t_lo < t_hi)) return;
  auto corner = [&](double t, int k, int vertex) {
    LabelledCorner c;
    c.p = s0 + t * (s1 - s0);
    const std::uint32_t own =
        k < 0 ? feature(FeatureType::kVertex, vertex) : feature(FeatureType::kEdge, edge);
    const std::uint32_t other = k < 0 ? feature(FeatureType::kFace, polygon.face)
                                      : feature(FeatureType::kEdge, polygon.edge[k]);
    c.a = segment_is_a ? own : other;
    c.b = segment_is_a ? other : own;
    return c;
  };
  out.push_back(corner(t_lo, k_lo, v0));
  out.push_back(corner(t_hi, k_hi, v1));
}

namespace {

const double kCosFacing = std::cos(kFacingAngleDeg * std::numbers::pi / 180.0);
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

ReferenceFaceContactBuilder::Facing ReferenceFaceContactBuilder::facingSide(const Body& body,
                                                                            const Vec3& direction,
                                                                            int support) {
  Facing f;
  f.face = facingFace(body, direction, support, f.normal);
  if (f.face >= 0) f.base = &body.vertices[body.shape->faces()[f.face].vertices[0]];
  return f;
}

LabelledPolygon ReferenceFaceContactBuilder::project(const Body& body, int face,
                                                     std::vector<Vec2>& corners,
                                                     std::vector<int>& vertex,
                                                     std::vector<int>& edge) const {
  const auto& f = body.shape->faces()[face];
  const int m = static_cast<int>(f.vertices.size());
  corners.resize(m);
  double twice_area = 0.0;
  for (int i = 0; i < m; ++i) {
    const Vec3 d = body.vertices[f.vertices[i]] - frame_.origin;
    corners[i] = Vec2(frame_.u.dot(d), frame_.v.dot(d));
  }
  for (int i = 0; i < m; ++i)
    twice_area += geometry::cross2(corners[i], corners[i + 1 < m ? i + 1 : 0]);
  if (twice_area >= 0.0) {  // counter-clockwise seen from +n already (B's face): the face's lists
    return {corners, f.vertices, f.edges, face};
  }
  // A face seen from its back (A's face looks along -n): reverse it. Edge i of the reversed
  // polygon joins reversed corners i and i + 1, i.e. the original edge m - 2 - i (mod m).
  std::reverse(corners.begin(), corners.end());
  vertex.resize(m);
  edge.resize(m);
  for (int i = 0; i < m; ++i) {
    vertex[i] = f.vertices[m - 1 - i];
    edge[i] = f.edges[m - 2 - i >= 0 ? m - 2 - i : m - 1];  // i = m - 1: edge m - 1
  }
  return {corners, vertex, edge, face};
}

void ReferenceFaceContactBuilder::fromCorner(const Body& a, const Body& b, const LabelledCorner& k,
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
}

bool ReferenceFaceContactBuilder::faceFace(const Body& a, const Body& b, const Contact& c) {
  const int fa = facing_a_.face, fb = facing_b_.face;
  clipper_.polygons(project(a, fa, corners_a_, vertex_a_, edge_a_),
                    project(b, fb, corners_b_, vertex_b_, edge_b_), RelTol::kPoint * scale_,
                    overlap_);
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
  pending_.resize(m);
  for (int i = 0; i < m; ++i) {
    const double weight = 0.5 * (shares_[i] + shares_[i > 0 ? i - 1 : m - 1]) / (0.5 * twice_area);
    pending_[i] = {featureKey(overlap_[i].a, overlap_[i].b), weight, i};
  }
  area_ = 0.5 * twice_area;
  finish(a, b, c.normal);
  return true;
}

bool ReferenceFaceContactBuilder::edgeFace(const Body& edge_body, const Body& face_body, int edge,
                                           bool edge_is_a, const Contact& c) {
  const int face = edge_is_a ? facing_b_.face : facing_a_.face;
  const LabelledPolygon polygon = project(face_body, face, corners_b_, vertex_b_, edge_b_);
  const auto& e = edge_body.shape->edges()[edge];
  auto flat = [&](int v) {
    const Vec3 d = edge_body.vertices[v] - frame_.origin;
    return Vec2(frame_.u.dot(d), frame_.v.dot(d));
  };
  const Vec2 s0 = flat(e.v0), s1 = flat(e.v1);
  clipper_.segment(s0, s1, e.v0, e.v1, edge, edge_is_a, polygon, overlap_);
  if (overlap_.size() != 2) return false;
  if (!((overlap_[1].p - overlap_[0].p).norm() > RelTol::kPoint * scale_)) return false;
  pending_.resize(2);
  for (int i = 0; i < 2; ++i) pending_[i] = {featureKey(overlap_[i].a, overlap_[i].b), 0.5, i};
  finish(edge_is_a ? edge_body : face_body, edge_is_a ? face_body : edge_body, c.normal);
  return true;
}

void ReferenceFaceContactBuilder::finish(const Body& a, const Body& b, const Vec3& n) {
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
      pending_[kept++] = pending_[i];
    }
  }
  subs_.resize(kept);
  for (std::size_t i = 0; i < kept; ++i) {
    fromCorner(a, b, overlap_[pending_[i].corner], n, pending_[i].weight, subs_[i]);
  }
}

FaceContact ReferenceFaceContactBuilder::build(const Body& a, const Body& b, const Contact& c) {
  const Vec3& n = c.normal;
  scale_ = pairLengthScale(a, b);
  area_ = 0.0;
  const Vec3 u = (std::abs(n.x()) < 0.6 ? Vec3::UnitX() : Vec3::UnitY()).cross(n).normalized();
  frame_ = {c.point, u, n.cross(u)};
  const int ia = supportIndex(a, -n), ib = supportIndex(b, n);
  facing_a_ = facingSide(a, -n, ia);
  facing_b_ = facingSide(b, n, ib);
  ContactArea kind = ContactArea::kPoint;
  if (facing_a_.face >= 0 && facing_b_.face >= 0) {
    if (faceFace(a, b, c)) kind = ContactArea::kFace;
  } else if (facing_b_.face >= 0) {
    const int ea = flatEdge(a, n, ia);
    if (ea >= 0 && edgeFace(a, b, ea, true, c)) kind = ContactArea::kLine;
  } else if (facing_a_.face >= 0) {
    const int eb = flatEdge(b, n, ib);
    if (eb >= 0 && edgeFace(b, a, eb, false, c)) kind = ContactArea::kLine;
  }
  if (kind != ContactArea::kPoint) {
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

}  // namespace polydem::contact::reference
