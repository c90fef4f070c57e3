#include "polydem/geometry/box_frame.h"

#include <algorithm>
#include <cmath>

#include "polydem/geometry/convex_polyhedron.h"

namespace polydem::geometry {

std::optional<BoxFrame> findBoxFrame(const ConvexPolyhedron& p) {
  const auto& v = p.vertices();
  if (v.size() != 8 || p.faces().size() != 6 || p.axisFaces().size() != 3 ||
      p.axisEdges().size() != 3) {
    return std::nullopt;
  }
  BoxFrame box;
  for (int k = 0; k < 3; ++k) box.axis[k] = p.faces()[p.axisFaces()[k]].normal;
  double skew =
      std::max({std::abs(box.axis[0].dot(box.axis[1])), std::abs(box.axis[1].dot(box.axis[2])),
                std::abs(box.axis[2].dot(box.axis[0]))});
  box.centre = Vec3::Zero();
  for (const Vec3& x : v) box.centre += x;
  box.centre /= 8.0;
  box.half = Vec3::Zero();
  for (const Vec3& x : v) {
    for (int k = 0; k < 3; ++k)
      box.half[k] = std::max(box.half[k], std::abs((x - box.centre).dot(box.axis[k])));
  }
  // Every corner at its own sign pattern, at +-h_k along every axis.
  box.corner.fill(-1);
  const double size = box.half.maxCoeff();
  for (int i = 0; i < 8; ++i) {
    int bits = 0;
    for (int k = 0; k < 3; ++k) {
      const double along = (v[i] - box.centre).dot(box.axis[k]);
      bits |= along > 0.0 ? 1 << k : 0;
      skew = std::max(skew, std::abs(std::abs(along) - box.half[k]) / size);
    }
    if (box.corner[bits] >= 0) return std::nullopt;
    box.corner[bits] = i;
  }
  for (int i = 0; i < 3; ++i) {
    const auto& edge = p.edges()[p.axisEdges()[i]];
    const Vec3 e = (v[edge.v1] - v[edge.v0]).normalized();
    int k = 0;
    for (int m = 1; m < 3; ++m) {
      if (std::abs(e.dot(box.axis[m])) > std::abs(e.dot(box.axis[k]))) k = m;
    }
    box.edge_axis[i] = k;
    box.edge_sign[i] = e.dot(box.axis[k]) > 0.0 ? 1.0 : -1.0;
    skew = std::max(skew, e.cross(box.axis[k]).norm());
  }
  // Each face along its own axis and sign. Not counted in the skew: a box's face normals are its
  // axes (or their opposites) within round-off, and the skew decides the box test's bounds.
  box.face.fill(-1);
  for (int f = 0; f < 6; ++f) {
    const Vec3& n = p.faces()[f].normal;
    int k = 0;
    for (int m = 1; m < 3; ++m) {
      if (std::abs(n.dot(box.axis[m])) > std::abs(n.dot(box.axis[k]))) k = m;
    }
    const int slot = 2 * k + (n.dot(box.axis[k]) > 0.0 ? 0 : 1);
    if (box.face[slot] >= 0) return std::nullopt;
    box.face[slot] = f;
  }
  box.skew = skew;
  if (!(skew <= BoxFrame::kMaxSkew)) return std::nullopt;
  return box;
}

}  // namespace polydem::geometry
