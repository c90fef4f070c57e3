// Vertex lists of the shapes used by scene files and benchmarks (BENCHMARKS.md section C). Each
// function returns the corners of a convex polyhedron; build it with
// ConvexPolyhedron::fromPoints(shapes::cube(1.0)). Invalid sizes throw GeometryError.
#pragma once

#include <cstdint>
#include <vector>

#include "polydem/core/types.h"

namespace polydem::geometry::shapes {

/// Axis-aligned box with opposite corners lo and hi (lo < hi in every coordinate).
std::vector<Vec3> box(const Vec3& lo, const Vec3& hi);
/// Axis-aligned box centred at `centre` with the given half-extents.
std::vector<Vec3> boxAround(const Vec3& centre, const Vec3& half_extents);

/// Prism: the convex polygon `base` (planar, in order) and its copy moved by `extrusion`.
std::vector<Vec3> prism(const std::vector<Vec3>& base, const Vec3& extrusion);

/// Triangular prism lying on a horizontal base with a horizontal ridge on top: the ridge runs from
/// ridge_a to ridge_b (same z), the base is the rectangle `height` below it, `base_half_width` to
/// either side of the ridge line. (BENCHMARKS.md C-VE: ridge (-1,0,0)-(1,0,0), 0.5, 1.)
std::vector<Vec3> ridgePrism(const Vec3& ridge_a, const Vec3& ridge_b, double base_half_width,
                             double height);

enum class Apex { kUp, kDown };
/// Square pyramid with its apex at `apex`, axis vertical, square base of side `base_side` at
/// `height` below (kUp) or above (kDown) the apex, turned by `turn` radians about the axis (0:
/// base edges along x and y).
std::vector<Vec3> squarePyramid(const Vec3& apex, double base_side, double height, Apex direction,
                                double turn = 0.0);

/// The Platonic solids, centred at the origin. Orientations: cube axis-aligned; tetrahedron with
/// corners on alternate cube corners (1,1,1), (1,-1,-1), (-1,1,-1), (-1,-1,1); octahedron with
/// corners on the axes; icosahedron on the cyclic permutations of (0, +-1, +-phi); dodecahedron on
/// (+-1, +-1, +-1) and the cyclic permutations of (0, +-1/phi, +-phi).
enum class Platonic { kTetrahedron, kCube, kOctahedron, kDodecahedron, kIcosahedron };
std::vector<Vec3> platonic(Platonic solid, double edge);
/// Circumradius / edge length of a Platonic solid.
double platonicCircumradiusPerEdge(Platonic solid);
/// The solid of the given circumradius instead of edge length.
std::vector<Vec3> platonicWithCircumradius(Platonic solid, double circumradius);

inline std::vector<Vec3> tetrahedron(double edge) {
  return platonic(Platonic::kTetrahedron, edge);
}
inline std::vector<Vec3> cube(double edge) {
  return platonic(Platonic::kCube, edge);
}
inline std::vector<Vec3> octahedron(double edge) {
  return platonic(Platonic::kOctahedron, edge);
}
inline std::vector<Vec3> dodecahedron(double edge) {
  return platonic(Platonic::kDodecahedron, edge);
}
inline std::vector<Vec3> icosahedron(double edge) {
  return platonic(Platonic::kIcosahedron, edge);
}

/// Hexagonal prism (a rod) centred at the origin, axis along z: regular hexagon of side `side`
/// (corners at distance `side` from the axis, one on +x), total length `length`.
std::vector<Vec3> hexagonalPrism(double side, double length);

/// The most points randomConvex() takes (and a scene's `random` shape): all of them are
/// corners of the hull, whose faces (about 2 n) the contact kernels test pair by pair, and whose
/// build takes seconds at this size. Far above any rock's need; far below a count that would
/// exhaust memory before the hull is built.
inline constexpr int kMaxRandomPoints = 100000;

/// `n` >= 4 points on an ellipsoid with the given semi-axes, centred at the origin, from
/// std::mt19937_64(seed); the same seed gives the same bits everywhere. Every point lies on the
/// strictly convex ellipsoid, so all n are corners of their hull (up to round-off coincidences).
/// The ellipsoid is perturbed per seed: each semi-axis is scaled by a factor in [1 - p, 1 + p].
/// GeometryError for n outside [4, kMaxRandomPoints], before anything is allocated.
std::vector<Vec3> randomConvex(int n, std::uint64_t seed, const Vec3& semi_axes = Vec3::Ones(),
                               double perturbation = 0.0);

}  // namespace polydem::geometry::shapes
