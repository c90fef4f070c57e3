// The labelled clip of labelled_clip.h specialised to the face contact of two rectangular boxes:
// A's facing quadrilateral, written in coordinates (alpha, beta) of B's facing rectangle in which
// that rectangle is the unit square, clipped by the square's four edge lines (a Sutherland-Hodgman
// clip, as box-box contact generators do). Each line's signed distance is then one subtraction
// (alpha, 1 - alpha, beta or 1 - beta) instead of a cross product, and a crossing lies exactly on
// its line. The labels are those of LabelledClipper::polygons (a vertex of A inside B's face, a
// vertex of B inside A's face, a crossing of an edge of each), so the sub-contact keys are the
// general path's wherever the clip is not degenerate.
#pragma once

#include <array>
#include <cstdint>

#include "polydem/contact/face/labelled_clip.h"
#include "polydem/core/types.h"

namespace polydem::contact {

/// A's facing face in B's unit-square coordinates, counter-clockwise seen from B's outside.
struct LabelledQuad {
  std::array<Vec2, 4> corners;
  std::array<int, 4> vertex;  // A's vertex id of corner i
  std::array<int, 4> edge;    // A's edge id of the edge from corner i to corner i + 1
  int face = -1;
};

/// B's facing face: the unit square's corners (0,0), (1,0), (1,1), (0,1) are B's vertices
/// vertex[0..3]; edge k joins corners k and k + 1.
struct LabelledSquare {
  std::array<int, 4> vertex;
  std::array<int, 4> edge;
  int face = -1;
};

/// Signed distance of `p` from the square's edge line k, >= 0 inside.
inline double squareSide(const Vec2& p, int k) {
  switch (k) {
    case 0:
      return p.y();
    case 1:
      return 1.0 - p.x();
    case 2:
      return 1.0 - p.y();
    default:
      return p.x();
  }
}

/// Puts `p` on the square's edge line k.
inline void onSquareSide(Vec2& p, int k) {
  if (k == 0) p.y() = 0.0;
  if (k == 1) p.x() = 1.0;
  if (k == 2) p.y() = 1.0;
  if (k == 3) p.x() = 0.0;
}

class SquareClipper {
 public:
  /// The most corners a clip keeps; a clip that would need more (only possible for corners
  /// scattered by round-off along a line) reports failure and the caller takes the general path.
  static constexpr int kMaxCorners = 16;

  /// Clips `a` by the square `b`; corners counter-clockwise into `out`. A corner within the
  /// merge distance of a line is moved onto it; corners closer than the merge distance to the
  /// previous one are dropped (distance squared: du2 * da^2 + dv2 * db^2 <=
  /// merge2, du2 and dv2 the squared side lengths). Returns the number of corners, or -1 when
  /// kMaxCorners would be exceeded. Crossings carry side_a (A's quad edge) and side_b (line k).
  int clip(const LabelledQuad& a, const LabelledSquare& b, double du2, double dv2, double merge2,
           std::array<LabelledCorner, kMaxCorners>& out);

 private:
  struct Working {
    LabelledCorner corner;
    std::int32_t carrier;  // the edge leaving this corner: >= 0 A's quad edge, < 0 line -1-k
  };
  std::array<Working, kMaxCorners> poly_, next_;
  std::array<double, kMaxCorners> h_;
};

}  // namespace polydem::contact
