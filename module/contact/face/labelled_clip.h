// Clipping convex polygons and segments in a plane while remembering where every corner comes
// from: a vertex of A lying inside B's face, a vertex of B inside A's face, or the crossing of an
// edge of A with an edge of B. The face-contact model (face_contact.h) turns each labelled corner
// into a sub-contact whose history is keyed by that label, so the label must not depend on the
// order in which the clipping happened to meet the corner.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "polydem/core/types.h"

namespace polydem::contact {

/// One feature of a polyhedron, packed into 32 bits: (type << 30) | index.
enum class FeatureType : std::uint32_t { kNone = 0, kVertex = 1, kEdge = 2, kFace = 3 };

inline std::uint32_t feature(FeatureType type, int index) {
  return (static_cast<std::uint32_t>(type) << 30) | static_cast<std::uint32_t>(index);
}
inline FeatureType featureType(std::uint32_t f) {
  return static_cast<FeatureType>(f >> 30);
}
inline int featureIndex(std::uint32_t f) {
  return static_cast<int>(f & ((1u << 30) - 1u));
}

/// A corner of a clipped polygon in 2D with the features of A and of B it lies on.
struct LabelledCorner {
  Vec2 p = Vec2::Zero();
  std::uint32_t a = 0;  // feature of A: the vertex, the edge (crossing) or the face (B's vertex)
  std::uint32_t b = 0;  // feature of B likewise
  // A crossing of two polygons' edges (polygons()): the crossing edges' positions in A's and B's
  // polygon (edge i joins corners i and i + 1), so that the builder finds their projected ends
  // without projecting them again; -1 for any other corner.
  std::int32_t side_a = -1, side_b = -1;
};

/// A convex polygon (counter-clockwise, 2D) of one body's face, with the body's feature ids.
struct LabelledPolygon {
  std::span<const Vec2> corners;
  std::span<const int> vertex;  // vertex id of corner i
  std::span<const int> edge;    // edge id of the edge from corner i to corner i + 1
  int face = -1;                // the face the polygon is a projection of
};

/// Intersections with labelled corners; the buffers keep their capacity, so a clipper reused for
/// every pair allocates nothing once warm.
class LabelledClipper {
 public:
  /// The intersection of A's polygon with B's (both convex, counter-clockwise), corners
  /// counter-clockwise. A corner of A inside B is labelled (vertex of A, face of B); a corner of B
  /// inside A (face of A, vertex of B); a crossing (edge of A, edge of B). Empty if they do not
  /// overlap. Corners closer than `merge` to the previous one are dropped (degenerate touching).
  void polygons(const LabelledPolygon& a, const LabelledPolygon& b, double merge,
                std::vector<LabelledCorner>& out);

  /// The part of a segment inside a convex counter-clockwise polygon: 0 or 2 corners. The segment
  /// belongs to `segment_is_a` ? A : B, runs from `s0` (vertex `v0`) to `s1` (vertex `v1`) along
  /// edge `edge`; the polygon is the other body's face. An end inside the polygon is labelled
  /// (vertex, face); an end cut by the polygon's edge k is a crossing (edge, edge k).
  void segment(const Vec2& s0, const Vec2& s1, int v0, int v1, int edge, bool segment_is_a,
               const LabelledPolygon& polygon, std::vector<LabelledCorner>& out);

 private:
  struct Working {
    LabelledCorner corner;
    std::int32_t
        carrier;  // the edge leaving this corner: >= 0 A's polygon edge, < 0 clip line -1-k
  };
  std::vector<Working> poly_, next_;
  std::vector<double> h_;
};

}  // namespace polydem::contact
