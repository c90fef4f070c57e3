// GJK intersection test on the Minkowski difference A - B (Gilbert, Johnson and Keerthi 1988; van
// den Bergen 2001 for the termination rules). A and B overlap iff the origin lies in A - B. The
// simplex sub-algorithm finds the closest point of the current simplex to the origin by Voronoi
// regions (edges and faces in coordinates relative to a vertex) and decides containment in a
// tetrahedron by signed volumes, so that a nearly flat simplex is never taken for containing the
// origin.
#pragma once

#include <array>

#include "polydem/contact/support.h"

namespace polydem::contact {

/// Up to four points of A - B with the vertices of A and B they came from.
struct Simplex {
  int size = 0;
  std::array<SupportPoint, 4> p;
};

struct GjkResult {
  bool separated = false;
  /// separated: unit axis from B into A with min over (A - B) of axis . x > 0 (A moves along it).
  Vec3 axis = Vec3::UnitZ();
  /// !separated: a simplex whose hull contains the origin, or comes within `tolerance` of it
  /// (a point, segment or triangle then; EPA blows it up to a tetrahedron).
  Simplex simplex;
  bool converged = true;  // false when the iteration bound was hit
  int iterations = 0;
};

/// Bound on GJK iterations; a polytope pair needs a handful, near-touching pairs a few more.
inline constexpr int kGjkMaxIterations = 64;

/// Runs GJK from `initial_axis` (a guess of the separating axis from B into A, need not be unit;
/// zero is replaced by x). `tolerance` (a length) is the distance below which the origin is taken
/// to lie on the simplex.
GjkResult gjkIntersect(MinkowskiSupport& support, const Vec3& initial_axis, double tolerance);

/// Closest point of the simplex's hull to the origin. Reduces the simplex to the vertices whose
/// hull holds that point (in their original order) and returns true, with v = 0 and the simplex
/// untouched, when it is a tetrahedron containing the origin (boundary included).
bool closestToOrigin(Simplex& simplex, Vec3& v);

}  // namespace polydem::contact
