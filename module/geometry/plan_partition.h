// A surface z(x, y) that is linear on each triangle of a triangulation in plan (x, y) and goes on
// outside the triangles' hull at the height of the hull's nearest point: constant along the
// hull's outward normals, beyond each hull edge (a strip, z linear along the edge), and constant
// in the corner between two strips at a hull vertex. The plan is cut into convex cells
// (triangles, strips, corners), each the intersection of half-planes whose lines are shared
// exactly by the two cells they separate, so the cells tile the plane without gap or overlap; z
// is continuous and linear on each cell.
//
// The resultant of the hydrostatic pressure below such a surface on a planar polygon (a face of a
// block) is the sum over the cells of the polygon's part in each (clipped in plan), each
// integrated exactly under that cell's linear pressure (face_pressure.h): no quadrature.
#pragma once

#include <array>
#include <map>
#include <span>
#include <utility>
#include <vector>

#include "polydem/core/types.h"
#include "polydem/geometry/face_pressure.h"
#include "polydem/geometry/plan_triangulation.h"

namespace polydem::geometry {

/// The plane z = height + slope_x (x - x0) + slope_y (y - y0).
struct PlanPlane {
  double x0 = 0.0, y0 = 0.0;
  double height = 0.0;
  double slope_x = 0.0, slope_y = 0.0;
  double at(double x, double y) const { return height + slope_x * (x - x0) + slope_y * (y - y0); }
};

class PlanPartition {
 public:
  /// The cells of `triangles` (counter-clockwise, from delaunayTriangulation) over `points`.
  PlanPartition(std::span<const PlanPoint> points, std::span<const PlanTriangle> triangles);

  std::size_t cellCount() const { return cells_.size(); }
  /// The surface on cell c through the heights `z` of the points.
  PlanPlane plane(std::size_t c, std::span<const double> z) const;
  /// The cell (x, y) lies in.
  std::size_t cellAt(double x, double y) const;

  /// The resultant of `pressure[c]` (one per cell) on the convex polygon points[polygon[k]] with
  /// outward `normal`, as pressureResultant (face_pressure.h), summed over the cells.
  /// `pressure`'s origins must be one point (moments about it).
  PressureResultant resultant(std::span<const Vec3> points, std::span<const int> polygon,
                              const Vec3& normal, std::span<const LinearPressure> pressure) const;

 private:
  struct Line {
    double a, b, x0, y0;  // f(x, y) = a (x - x0) + b (y - y0)
    double at(double x, double y) const { return a * (x - x0) + b * (y - y0); }
  };
  struct Side {
    int line;
    bool closed;  // keep f >= 0; else keep f < 0
  };
  enum class Kind { kTriangle, kStrip, kCorner };
  struct Cell {
    Kind kind;
    std::array<int, 3> corner;  // triangle: its points; strip: from, to; corner: its point
    std::vector<Side> sides;
    double lo[2], hi[2];    // triangle: its box in plan
    double tx = 0, ty = 0;  // strip: the direction of its hull side
  };

  int pairLine(int i, int j);
  int normalLine(int side, double tx, double ty, int point);
  void addTriangle(const PlanTriangle& t);
  void addHull(const std::vector<int>& hull);
  bool inside(const Cell& c, double x, double y) const;
  /// The part of the polygon `in` on `c`, into `in` (`work`: a buffer).
  void clip(const Cell& c, std::vector<Vec3>& in, std::vector<Vec3>& work) const;

  std::vector<PlanPoint> points_;
  std::vector<Line> lines_;
  std::vector<Cell> cells_;
  std::map<std::pair<int, int>, int> pair_lines_;    // (i < j) -> the line through points i, j
  std::map<std::pair<int, int>, int> normal_lines_;  // (side, point) -> the line through the
                                                     // point across the hull side
};

}  // namespace polydem::geometry
