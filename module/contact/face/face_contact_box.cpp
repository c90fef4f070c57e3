// The box-face path of the sub-contact builder (face_contact.h): the face contact of two
// rectangular boxes (geometry/box_frame.h) whose faces face each other, which is every contact of
// a dense pack of aligned blocks. The model is the general path's (the same facing faces, corner
// labels and keys, weights rule, gaps along the same normals), computed with less work:
//   - the facing face of each box is the face along its axis closest to the normal, from the
//     shape's table (BoxFrame::face), with no search over faces or support scan;
//   - A's face is projected along the contact normal n onto the plane of B's face and written in
//     coordinates (alpha, beta) in which B's rectangle x0 + alpha U + beta V is the unit square:
//     three dot products a corner, and B's corners need no projection;
//   - the clip's line distances are single subtractions (square_clip.h);
//   - a crossing is lifted onto B's edge from its coordinate along the edge (no division) and
//     onto A's edge from that edge's two line distances (one division).
// The projection along n onto B's plane and the projection onto the plane normal to n (the general
// path's) are related by an affine map, which keeps the labels, the area shares (ratios of
// areas) and the points on each edge; the results differ by round-off, and in degenerate clips (a
// corner on an edge line within round-off) a corner may be labelled as a crossing by one path and
// as a vertex by the other. A pair of boxes always takes this path, so its keys are consistent
// from step to step.
#include <algorithm>
#include <cmath>
#include <numbers>

#include "polydem/contact/face/face_contact.h"
#include "polydem/contact/face/square_clip.h"
#include "polydem/core/tolerance.h"
#include "polydem/geometry/box_frame.h"
#include "polydem/geometry/polygon.h"

namespace polydem::contact {

[[gnu::always_inline]] inline FaceContactBuilder::Facing FaceContactBuilder::boxFacing(
    const Body& body, const Vec3& direction) {
  // A face within the facing angle (20 deg) of `direction` lies along the box axis a_k closest to
  // it, on the side of the sign of a_k . direction: |a_k . direction| >= cos 20 deg there, and
  // <= sin 20 deg along the other two axes. So that face, from the shape's table, is the only
  // candidate, and its own cosine decides as in a search over all six faces (no two faces are
  // within 40 degrees of each other, so the search never had a tie to break).
  const geometry::BoxFrame& box = *body.shape->box();
  const auto& axis_faces = body.shape->axisFaces();
  int k = 0;
  double c = 0.0;
  for (int m = 0; m < 3; ++m) {
    const double cm = body.faceNormal(axis_faces[m]).dot(direction);
    if (std::abs(cm) > std::abs(c)) k = m, c = cm;
  }
  Facing f;
  const int face = box.face[2 * k + (c > 0.0 ? 0 : 1)];
  // The face +a_k is axis_faces[k] itself: its cosine is c, the value the search computed.
  const double cos_face = c > 0.0 ? c : body.faceNormal(face).dot(direction);
  if (!(cos_face > kCosFacing)) return f;
  f.face = face;
  f.normal = body.faceNormal(face);
  f.base = &body.vertices[body.shape->faces()[face].vertices[0]];
  return f;
}

bool FaceContactBuilder::boxFaceFace(const Body& a, const Body& b, const Contact& c,
                                     ContactArea& kind) {
  const Vec3& n = c.normal;
  const Facing fa = boxFacing(a, -n), fb = boxFacing(b, n);
  if (fa.face < 0 || fb.face < 0) return false;
  const auto& face_a = a.shape->faces()[fa.face];
  const auto& face_b = b.shape->faces()[fb.face];
  if (face_a.vertices.size() != 4 || face_b.vertices.size() != 4) return false;
  facing_a_ = fa;
  facing_b_ = fb;
  // B's face, counter-clockwise about its outward normal nb (~ n): x0 + alpha U + beta V with
  // U = x1 - x0 and V = x3 - x0 orthogonal, so alpha = (x - x0) . U / |U|^2 for x on the plane.
  for (int k = 0; k < 4; ++k) {
    square_.vertex[k] = face_b.vertices[k];
    square_.edge[k] = face_b.edges[k];
    world_b_[k] = &b.vertices[face_b.vertices[k]];
  }
  square_.face = fb.face;
  const Vec3& x0 = *world_b_[0];
  const Vec3 u = *world_b_[1] - x0, v = *world_b_[3] - x0;
  const double uu = u.squaredNorm(), vv = v.squaredNorm();
  const Vec3 du = u * (1.0 / uu), dv = v * (1.0 / vv);
  const Vec3& nb = fb.normal;
  const double nn = n.dot(nb);  // > cos 20 deg: both faces face
  const double per_nn = 1.0 / nn;
  const double n_u = n.dot(du) * per_nn, n_v = n.dot(dv) * per_nn;
  // A's face seen from its back, reversed (as project() does): corner i is the face's vertex
  // 3 - i, and edge i joins corners i and i + 1 (the face's edge 2 - i, edge 3 for i = 3). A
  // corner x moves along n onto B's plane, x - s n with s = (x - x0) . nb / (n . nb).
  for (int i = 0; i < 4; ++i) {
    const int id = face_a.vertices[3 - i];
    quad_.vertex[i] = id;
    quad_.edge[i] = face_a.edges[i < 3 ? 2 - i : 3];
    world_a_[i] = &a.vertices[id];
    const Vec3 d = a.vertices[id] - x0;
    const double s = d.dot(nb);
    quad_.corners[i] = Vec2(d.dot(du) - s * n_u, d.dot(dv) - s * n_v);
  }
  quad_.face = fa.face;
  const double merge = RelTol::kPoint * scale_;
  const int m = square_clipper_.clip(quad_, square_, uu, vv, merge * merge, box_overlap_);
  if (m < 0) return false;  // round-off scattered corners along a line: the general path
  kind = ContactArea::kPoint;
  if (m < 3) return true;
  // Shares and weights as faceFace() (the mean of the corners maps to the mean, and ratios of
  // areas are kept by the affine map), in unit-square coordinates.
  Vec2 middle = Vec2::Zero();
  for (int i = 0; i < m; ++i) middle += box_overlap_[i].p;
  middle *= 1.0 / static_cast<double>(m);
  double twice = 0.0, extent2 = 0.0;
  shares_.resize(m);
  for (int i = 0; i < m; ++i) {
    const Vec2& p = box_overlap_[i].p;
    const Vec2& q = box_overlap_[i + 1 < m ? i + 1 : 0].p;
    shares_[i] = std::max(0.5 * geometry::cross2(p - middle, q - middle), 0.0);
    twice += 2.0 * shares_[i];
    const Vec2 side = p - q;
    extent2 = std::max(extent2, uu * side.x() * side.x() + vv * side.y() * side.y());
  }
  // The sliver test of faceFace() in B's plane: twice the area |U||V| twice against the longest
  // side, squared (both sides are >= 0) to save the square root of the side.
  const double uv = std::sqrt(uu * vv);
  const double twice_area = twice * uv;
  const double floor = 2.0 * RelTol::kIteration * scale_;
  if (!(twice_area > 0.0 && twice_area * twice_area > floor * floor * extent2)) return true;
  const double per_twice = 1.0 / twice;  // weight i: (share i + share i-1) / (twice the area)
  pending_.resize(m);
  for (int i = 0; i < m; ++i) {
    const double weight = (shares_[i] + shares_[i > 0 ? i - 1 : m - 1]) * per_twice;
    pending_[i] = {featureKey(box_overlap_[i].a, box_overlap_[i].b), weight, i};
  }
  area_ = 0.5 * twice_area * nn;  // projected onto the plane normal to n, as faceFace()'s
  sortPending();
  subs_.resize(pending_.size());
  for (std::size_t i = 0; i < pending_.size(); ++i) {
    fromBoxCorner(a, b, box_overlap_[pending_[i].corner], n, pending_[i].weight, subs_[i]);
  }
  kind = ContactArea::kFace;
  return true;
}

[[gnu::always_inline]] inline void FaceContactBuilder::fromBoxCorner(const Body& a, const Body& b,
                                                                     const LabelledCorner& k,
                                                                     const Vec3& n, double weight,
                                                                     SubContact& s) const {
  s.weight = weight;
  s.feature = featureKey(k.a, k.b);
  if (featureType(k.a) == FeatureType::kVertex) {  // A's vertex inside B's face, as fromCorner()
    const Vec3& nb = facing_b_.normal;
    const Vec3& x = a.vertices[featureIndex(k.a)];
    s.normal = nb;
    s.gap = nb.dot(*facing_b_.base - x);
    s.point = x + (0.5 * s.gap) * nb;
  } else if (featureType(k.b) == FeatureType::kVertex) {  // B's vertex inside A's face
    const Vec3& na = facing_a_.normal;
    const Vec3& x = b.vertices[featureIndex(k.b)];
    s.normal = -na;
    s.gap = na.dot(*facing_a_.base - x);
    s.point = x + (0.5 * s.gap) * na;
  } else {  // A's quad edge side_a crosses the square's line side_b
    const int i = k.side_a, i1 = (i + 1) & 3, l = k.side_b, l1 = (l + 1) & 3;
    // A's edge at its own line distances: the same point on the whole edge as on the clipped
    // piece the crossing came from.
    const double h0 = squareSide(quad_.corners[i], l), h1 = squareSide(quad_.corners[i1], l);
    const double t = h0 != h1 ? h0 / (h0 - h1) : 0.5;
    const Vec3 pa = *world_a_[i] + t * (*world_a_[i1] - *world_a_[i]);
    // B's edge l runs from corner l to l + 1; the crossing's coordinate along it.
    const double along = l == 0   ? k.p.x()
                         : l == 1 ? k.p.y()
                         : l == 2 ? 1.0 - k.p.x()
                                  : 1.0 - k.p.y();
    const Vec3 pb = *world_b_[l] + along * (*world_b_[l1] - *world_b_[l]);
    s.normal = n;
    s.gap = n.dot(pb - pa);
    s.point = 0.5 * (pa + pb);
  }
}

}  // namespace polydem::contact
