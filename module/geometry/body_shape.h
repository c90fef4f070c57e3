// BodyShape: a particle shape in its body frame (centroid at the origin, axes along the principal
// axes of inertia) with its mass properties per unit density. Particles carry an id into one table
// of BodyShapes that every rank holds; messages and checkpoints carry the id, not the mesh. Shapes
// whose body-frame polyhedra are the same to the last bit (the congruent blocks of a rock mass cut
// on exactly representable planes) share one polyhedron (shape_sharing.h); each keeps its own
// joint plane per face.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "polydem/geometry/convex_polyhedron.h"

namespace polydem::geometry {

struct BodyShape {
  std::string name;
  /// Body frame; never null once built, possibly shared with other shapes (read only).
  std::shared_ptr<const ConvexPolyhedron> polyhedron = std::make_shared<const ConvexPolyhedron>();
  double volume = 0.0;
  Vec3 principal_moments = Vec3::Zero();  // diagonal inertia per unit density, body frame
  double circumradius = 0.0;
  double inradius = 0.0;
  /// Per face of `polyhedron`: the joint plane it lies on (an index into the scene's joint
  /// planes, setup::Setup::joint_planes), -1 for a face not made by a joint. Empty: no face is.
  std::vector<std::int32_t> face_plane;
  /// The joint plane of face `f`, -1 if none.
  std::int32_t facePlane(int f) const {
    return face_plane.empty() ? -1 : face_plane[static_cast<std::size_t>(f)];
  }
};

/// A shape given in some input frame, moved to its body frame. `input_from_body` is the rigid
/// motion that puts the body-frame shape back where the input was: x_input = R x_body + c.
/// When the inertia tensor is already diagonal (to 1e-12 relative) R is the identity, so shapes
/// given axis-aligned keep their exact coordinates.
struct BodyFrameResult {
  BodyShape shape;
  Quat rotation;  // R above
  Vec3 centroid;  // c above
};
BodyFrameResult toBodyFrame(const ConvexPolyhedron& input, std::string name = {});

}  // namespace polydem::geometry
