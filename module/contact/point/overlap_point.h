// The centre of pressure of a linear elastic bed as the contact point of a single-point kernel.
//
// A penalty kernel puts the whole normal force kn * depth at one point. If the bed between two
// bodies were a layer of independent springs (a Winkler foundation), the pressure at a point of
// the contact plane would be proportional to the local penetration, the length of the overlap
// A ∩ B along the normal there; the resultant then acts on the line through the centroid of the
// overlap VOLUME parallel to the normal. For a face-face contact that point moves towards the low
// edge as soon as a block tilts (linearly in the tilt), which gives the contact a rotational
// stiffness; the IPM point (the centroid of the overlap polygon) does not move while the whole
// face still overlaps. See docs/dynamics.md, "Single-point contact and rocking".
//
// The volume and centroid of A ∩ B follow from its boundary by the divergence theorem: the
// boundary is every face of A clipped by B's planes plus every face of B clipped by A's planes;
// each piece is fanned into tetrahedra with a common apex near the overlap.
#pragma once

#include <span>
#include <vector>

#include "polydem/contact/contact.h"
#include "polydem/geometry/polygon_clip.h"

namespace polydem::contact {

/// Volume and centroid of the intersection of two placed convex polyhedra.
struct OverlapVolume {
  bool found = false;  // false: no overlap thicker than the plane tolerance (touching, apart)
  double volume = 0.0;
  Vec3 centroid = Vec3::Zero();
};

/// Computes A ∩ B and moves contact points to its centroid. Holds reusable buffers: once they
/// have grown to the largest pair, no allocation.
class OverlapCentroid {
 public:
  /// The intersection of `a` and `b`. `apex` is a point near the overlap (the kernel's contact
  /// point): the tetrahedra of the fan share it, so cancellation stays small.
  OverlapVolume intersect(const Body& a, const Body& b, const Vec3& apex);

  /// `contact` with its point moved to the line through the centroid of A ∩ B along the contact
  /// normal, at the kernel point's height along the normal (so only the lateral position, the
  /// lever arm of the normal force, changes). Unchanged when the contact is not touching or the
  /// overlap has no volume (exactly touching faces).
  Contact apply(const Body& a, const Body& b, const Contact& contact);

 private:
  struct WorldPlane {
    Vec3 normal;
    double offset;  // normal . x = offset on the plane
  };
  static void worldPlanes(const Body& body, std::vector<WorldPlane>& planes);
  // Whether face f of `body` lies in `plane` (all its corners within `tolerance`).
  static bool faceOnPlane(const Body& body, int f, const WorldPlane& plane, double tolerance);
  // Adds the pieces of `own`'s faces inside `other` to the sums; faces of `own` listed in
  // `skip_face` are left out, planes of `other` listed in `skip_plane` are not clipped by.
  void addFaces(const Body& own, const std::vector<WorldPlane>& other_planes,
                const std::vector<char>& skip_face, const std::vector<int>& skip_plane_of_face,
                const Vec3& apex);

  geometry::ConvexPolygonClipper clipper_;
  std::vector<WorldPlane> planes_a_, planes_b_;
  std::vector<char> skip_b_;
  std::vector<int> twin_of_a_, none_;
  double volume_ = 0.0, abs_volume_ = 0.0, area_ = 0.0;
  Vec3 moment_ = Vec3::Zero();  // sum of tetrahedron volume * (centroid - apex)
};

}  // namespace polydem::contact
