// The heap a table of body shapes holds, by part of a shape, counted from what is allocated
// (capacities times element sizes, core/memory.h) together with the number of heap blocks: the
// same figures on any machine for the same build and input, so that a test can assert them.
// Glibc adds about 8-16 bytes to each block, which the counted bytes leave out and the process's
// resident memory includes; the block count says how much that is.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "polydem/geometry/body_shape.h"

namespace polydem::geometry {

struct ShapeMemoryItem {
  std::string name;  // short, for a table
  std::string what;  // what it holds
  std::uint64_t bytes = 0;
  std::uint64_t blocks = 0;  // heap allocations
};

/// The parts in a fixed order: the shape records themselves, the polyhedron records, names,
/// vertices, faces (the records), the faces' vertex and edge lists, edges, the vertex adjacency,
/// the separating axes, the joint plane of each face. A polyhedron shared by several shapes counts
/// once.
std::vector<ShapeMemoryItem> shapeMemory(std::span<const BodyShape> shapes);

}  // namespace polydem::geometry
