// Joint identity of a shape's faces: which of the scene's joint planes (setup::JointPlaneSpec)
// each face of a cut block lies on. The scene gives the planes of a block in the block's input
// frame (setup::ShapeSpec::face_planes); the shape table holds the hull in its body frame, so
// each face is taken back to the input frame and matched there.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "polydem/core/types.h"
#include "polydem/geometry/body_shape.h"
#include "polydem/setup/setup.h"

namespace polydem::sim {

/// Per face of `shape` (body frame, placed in the input frame by x_input = rotation x + centroid):
/// the plane of `planes` the face lies on (parallel normals, and the face's centroid on the
/// plane, both to a tolerance relative to the shape's size and distance from the origin), else
/// -1. Empty if `planes` is.
std::vector<std::int32_t> matchFacePlanes(const geometry::BodyShape& shape, const Quat& rotation,
                                          const Vec3& centroid,
                                          std::span<const setup::FacePlane> planes);

}  // namespace polydem::sim
