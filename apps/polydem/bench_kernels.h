// polydem bench kernels (BENCHMARKS.md P-KERNELS): contact resolutions per second on one core for
// every registered kernel and for libccd's GJK+EPA and MPR, on three pre-generated sets of
// overlapping pairs, and the contact-point error against the exact centre of the overlap patch on
// the face-face set.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "polydem/contact/contact.h"
#include "polydem/geometry/convex_polyhedron.h"

namespace polydem::app {

/// Overlapping pairs (A, B) sharing storage for their shapes and world vertices.
struct PairSet {
  std::string name;  // face-face | random-cubes | random-polyhedra
  std::vector<std::unique_ptr<geometry::ConvexPolyhedron>> shapes;
  std::vector<std::vector<Vec3>> world;  // world vertices, one list per body, never resized
  std::vector<contact::Body> a, b;
  std::vector<Vec3> exact_point;  // face-face: centre of the overlap patch, half way through
  std::size_t size() const { return a.size(); }
};

/// (a) unit cubes, A on B, penetration log-uniform in [1e-5, 1e-3], A shifted by up to 0.2 and
/// turned by up to 45 degrees about the vertical, the pair in a random pose.
PairSet faceFacePairs(int n, std::uint64_t seed);
/// (b) unit cubes in random orientations with centres 0.6 .. 1 apart (always overlapping).
PairSet randomCubePairs(int n, std::uint64_t seed);
/// (c) random convex polyhedra of 8-40 vertices, semi-axes 0.5 .. 1, random poses, inscribed
/// spheres overlapping (so the pair overlaps).
PairSet randomPolyhedronPairs(int n, std::uint64_t seed);

int benchKernels(int argc, char** argv);

}  // namespace polydem::app
