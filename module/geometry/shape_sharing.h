// Sharing of body-frame polyhedra between shapes. A rock mass cut by joint sets gives each block
// a shape of its own (each face records its joint plane, BodyShape::face_plane), but blocks cut
// on exactly representable planes (orthogonal sets on whole metres) are congruent to the last bit
// in their body frames: they can keep one polyhedron, and each block only its joint planes.
// Only polyhedra equal in every stored bit are shared (vertices, faces, edges, adjacency, axes,
// box frame, mass properties, radii), so every kernel reads the same numbers as it would from a
// copy of its own, and the results do not change.
#pragma once

#include <cstdint>
#include <memory>
#include <unordered_map>
#include <vector>

#include "polydem/geometry/convex_polyhedron.h"

namespace polydem::geometry {

/// Whether `a` and `b` hold the same bits in every stored member (the lazily computed face
/// regions, a function of the rest, excepted).
bool sameBits(const ConvexPolyhedron& a, const ConvexPolyhedron& b);

/// The polyhedra seen so far, by a hash of their vertices and face planes.
class PolyhedronPool {
 public:
  /// The pooled polyhedron with the same bits as `p` (sameBits), else `p` itself, now pooled.
  std::shared_ptr<const ConvexPolyhedron> share(std::shared_ptr<const ConvexPolyhedron> p);
  /// How many distinct polyhedra the pool holds.
  std::size_t distinct() const { return distinct_; }

 private:
  std::unordered_map<std::uint64_t, std::vector<std::shared_ptr<const ConvexPolyhedron>>> by_hash_;
  std::size_t distinct_ = 0;
};

}  // namespace polydem::geometry
