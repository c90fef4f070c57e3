#include "polydem/sim/face_planes.h"

#include <cmath>

namespace polydem::sim {

std::vector<std::int32_t> matchFacePlanes(const geometry::BodyShape& shape, const Quat& rotation,
                                          const Vec3& centroid,
                                          std::span<const setup::FacePlane> planes) {
  std::vector<std::int32_t> out;
  if (planes.empty()) return out;
  // The cut's vertices carry round-off relative to their coordinates; the hull and the move to
  // the body frame add a few ulps more. 1e-9 of the size is far above that and far below any
  // spacing of joint planes a scene can use.
  const double cos_parallel = 1.0 - 1e-9;
  const double reach = shape.circumradius + centroid.norm();
  const double tolerance = 1e-9 * reach;
  const auto& faces = shape.polyhedron->faces();
  out.assign(faces.size(), -1);
  for (std::size_t f = 0; f < faces.size(); ++f) {
    const Vec3 n = rotation * faces[f].normal;
    const Vec3 x = rotation * faces[f].centroid + centroid;
    for (const setup::FacePlane& p : planes) {
      if (std::abs(n.dot(p.normal)) >= cos_parallel &&
          std::abs(p.normal.dot(x) - p.offset) <= tolerance) {
        out[f] = p.plane;
        break;
      }
    }
  }
  return out;
}

}  // namespace polydem::sim
