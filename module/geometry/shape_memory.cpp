// shapeMemory: a shape table's heap by part (geometry/shape_memory.h).
#include "polydem/geometry/shape_memory.h"

#include <unordered_set>

#include "polydem/core/memory.h"

namespace polydem::geometry {

namespace {

// Adds a vector's capacity to `item`: its bytes and, when it holds any, one heap block.
template <typename T>
void add(ShapeMemoryItem& item, const std::vector<T>& v) {
  item.bytes += capacityBytes(v);
  item.blocks += v.capacity() > 0 ? 1 : 0;
}

// A std::string's own heap: none while it fits the small-string buffer (15 characters).
void addString(ShapeMemoryItem& item, const std::string& s) {
  if (s.capacity() > 15) {
    item.bytes += s.capacity() + 1;
    item.blocks += 1;
  }
}

enum Part {
  kRecords,
  kPolyhedra,
  kNames,
  kVertices,
  kFaces,
  kFaceLists,
  kEdges,
  kAdjacency,
  kAxes,
  kPlanes
};

// The shared_ptr's block holding the polyhedron (make_shared: object and counts together).
constexpr std::uint64_t kSharedCounts = 16;

void addPolyhedron(std::vector<ShapeMemoryItem>& out, const ConvexPolyhedron& p) {
  out[kPolyhedra].bytes += sizeof(ConvexPolyhedron) + kSharedCounts;
  out[kPolyhedra].blocks += 1;
  add(out[kVertices], p.vertices());
  add(out[kFaces], p.faces());
  for (const auto& f : p.faces()) {
    add(out[kFaceLists], f.vertices);
    add(out[kFaceLists], f.edges);
  }
  add(out[kEdges], p.edges());
  add(out[kAxes], p.axisFaces());
  add(out[kAxes], p.axisEdges());
  const VertexAdjacency& a = p.vertexAdjacency();
  for (const auto* list : {&a.begin, &a.edges, &a.faces, &a.neighbours})
    add(out[kAdjacency], *list);
}

}  // namespace

std::vector<ShapeMemoryItem> shapeMemory(std::span<const BodyShape> shapes) {
  std::vector<ShapeMemoryItem> out = {
      {"records", "BodyShape records (name, mass properties, radii, polyhedron pointer)"},
      {"polyhedra", "polyhedron records (mass properties, box frame, list headers), shared"},
      {"names", "shape names longer than the small-string buffer"},
      {"vertices", "vertex coordinates"},
      {"faces", "face records (normal, offset, centroid, area, list headers)"},
      {"face_lists", "each face's vertex and edge indices"},
      {"edges", "edge records (two vertices, two faces)"},
      {"adjacency", "edges, faces and neighbours of each vertex"},
      {"axes", "separating axes (face and edge indices)"},
      {"face_planes", "the joint plane of each face"},
  };
  out[kRecords].bytes = shapes.size() * sizeof(BodyShape);
  std::unordered_set<const ConvexPolyhedron*> seen;
  for (const auto& s : shapes) {
    addString(out[kNames], s.name);
    add(out[kPlanes], s.face_plane);
    if (seen.insert(s.polyhedron.get()).second) addPolyhedron(out, *s.polyhedron);
  }
  return out;
}

}  // namespace polydem::geometry
