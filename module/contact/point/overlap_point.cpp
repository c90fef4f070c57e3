#include "polydem/contact/point/overlap_point.h"

#include <cmath>

#include "polydem/core/tolerance.h"

namespace polydem::contact {

void OverlapCentroid::worldPlanes(const Body& body, std::vector<WorldPlane>& planes) {
  const auto& faces = body.shape->faces();
  planes.resize(faces.size());
  for (std::size_t f = 0; f < faces.size(); ++f) {
    const Vec3 n = body.faceNormal(static_cast<int>(f));
    planes[f] = {n, n.dot(body.vertices[faces[f].vertices[0]])};
  }
}

bool OverlapCentroid::faceOnPlane(const Body& body, int f, const WorldPlane& plane,
                                  double tolerance) {
  for (int v : body.shape->faces()[f].vertices) {
    if (std::abs(plane.normal.dot(body.vertices[v]) - plane.offset) > tolerance) return false;
  }
  return true;
}

void OverlapCentroid::addFaces(const Body& own, const std::vector<WorldPlane>& other_planes,
                               const std::vector<char>& skip_face,
                               const std::vector<int>& skip_plane_of_face, const Vec3& apex) {
  const auto& faces = own.shape->faces();
  for (std::size_t f = 0; f < faces.size(); ++f) {
    if (!skip_face.empty() && skip_face[f]) continue;
    const int skip_plane = skip_plane_of_face.empty() ? -1 : skip_plane_of_face[f];
    clipper_.assign(own.vertices, faces[f].vertices);
    bool inside = true;
    for (std::size_t p = 0; p < other_planes.size() && inside; ++p) {
      if (static_cast<int>(p) == skip_plane) continue;
      inside = clipper_.clip(other_planes[p].normal, -other_planes[p].offset);
    }
    const auto& poly = clipper_.polygon();
    if (!inside || poly.size() < 3) continue;
    // Fan of tetrahedra (apex, q0, qi, qi+1): the corners run counter-clockwise seen from
    // outside, so each volume is positive when the apex lies inside (divergence theorem).
    const Vec3 q0 = poly[0] - apex;
    for (std::size_t i = 1; i + 1 < poly.size(); ++i) {
      const Vec3 qi = poly[i] - apex, qj = poly[i + 1] - apex;
      const Vec3 cross = qi.cross(qj);
      const double v = q0.dot(cross) / 6.0;
      volume_ += v;
      abs_volume_ += std::abs(v);
      moment_ += v * 0.25 * (q0 + qi + qj);  // the apex is the origin of the q's
      area_ += 0.5 * (qi - q0).cross(qj - q0).norm();
    }
  }
}

OverlapVolume OverlapCentroid::intersect(const Body& a, const Body& b, const Vec3& apex) {
  worldPlanes(a, planes_a_);
  worldPlanes(b, planes_b_);
  const double tolerance = absTol(a.circumradius() + b.circumradius(), RelTol::kPlane);

  // A face of A and a face of B in one plane with the same outward normal bound A ∩ B by the same
  // polygon: count it once, from A's side (and do not clip A's face by the plane it lies in).
  twin_of_a_.assign(planes_a_.size(), -1);
  skip_b_.assign(planes_b_.size(), 0);
  for (std::size_t fa = 0; fa < planes_a_.size(); ++fa) {
    for (std::size_t fb = 0; fb < planes_b_.size(); ++fb) {
      if (skip_b_[fb] || planes_a_[fa].normal.dot(planes_b_[fb].normal) < 0.5) continue;
      if (faceOnPlane(b, static_cast<int>(fb), planes_a_[fa], tolerance)) {
        twin_of_a_[fa] = static_cast<int>(fb);
        skip_b_[fb] = 1;
        break;
      }
    }
  }

  volume_ = abs_volume_ = area_ = 0.0;
  moment_.setZero();
  addFaces(a, planes_b_, {}, twin_of_a_, apex);
  addFaces(b, planes_a_, skip_b_, none_, apex);

  OverlapVolume out;
  // A solid overlap is thicker (volume / boundary area) than the plane tolerance, and its volume
  // is not the residue of cancelling tetrahedra (two touching faces give +S h and -S h).
  if (volume_ > tolerance * area_ && volume_ > 1e-9 * abs_volume_) {
    out.found = true;
    out.volume = volume_;
    out.centroid = apex + moment_ / volume_;
  }
  return out;
}

Contact OverlapCentroid::apply(const Body& a, const Body& b, const Contact& contact) {
  if (!contact.touching) return contact;
  const OverlapVolume v = intersect(a, b, contact.point);
  if (!v.found) return contact;
  Contact moved = contact;
  const Vec3& n = contact.normal;
  moved.point = v.centroid + n * n.dot(contact.point - v.centroid);
  return moved;
}

}  // namespace polydem::contact
