// Cells of a triangulated surface and its continuation beyond the hull (plan_partition.h).
#include "polydem/geometry/plan_partition.h"

#include <algorithm>
#include <cmath>
#include <set>

namespace polydem::geometry {

PlanPartition::PlanPartition(std::span<const PlanPoint> points,
                             std::span<const PlanTriangle> triangles)
    : points_(points.begin(), points.end()) {
  std::set<std::pair<int, int>> directed;
  for (const auto& t : triangles) {
    addTriangle(t);
    for (int e = 0; e < 3; ++e) directed.insert({t[e], t[(e + 1) % 3]});
  }
  // The hull: the edges no other triangle shares, counter-clockwise.
  std::map<int, int> next;
  for (const auto& [a, b] : directed) {
    if (!directed.count({b, a})) next[a] = b;
  }
  std::vector<int> hull{next.begin()->first};
  while (next.at(hull.back()) != hull.front()) hull.push_back(next.at(hull.back()));
  addHull(hull);
}

int PlanPartition::pairLine(int i, int j) {
  const auto key = std::minmax(i, j);
  const auto found = pair_lines_.find(key);
  if (found != pair_lines_.end()) return found->second;
  // Positive on the left of the lower point to the higher.
  const PlanPoint& p = points_[static_cast<std::size_t>(key.first)];
  const PlanPoint& q = points_[static_cast<std::size_t>(key.second)];
  lines_.push_back({-(q[1] - p[1]), q[0] - p[0], p[0], p[1]});
  return pair_lines_[key] = static_cast<int>(lines_.size() - 1);
}

int PlanPartition::normalLine(int side, double tx, double ty, int point) {
  const auto found = normal_lines_.find({side, point});
  if (found != normal_lines_.end()) return found->second;
  const PlanPoint& p = points_[static_cast<std::size_t>(point)];
  lines_.push_back({tx, ty, p[0], p[1]});  // positive ahead of the point along the side
  return normal_lines_[{side, point}] = static_cast<int>(lines_.size() - 1);
}

void PlanPartition::addTriangle(const PlanTriangle& t) {
  Cell c{Kind::kTriangle, t, {}, {0, 0}, {0, 0}};
  for (int e = 0; e < 3; ++e) {
    const int a = t[e], b = t[(e + 1) % 3];
    c.sides.push_back({pairLine(a, b), a < b});  // the inside is on the left of a -> b
  }
  for (int k = 0; k < 2; ++k) {
    c.lo[k] = std::min({points_[t[0]][k], points_[t[1]][k], points_[t[2]][k]});
    c.hi[k] = std::max({points_[t[0]][k], points_[t[1]][k], points_[t[2]][k]});
  }
  cells_.push_back(std::move(c));
}

void PlanPartition::addHull(const std::vector<int>& hull) {
  const std::size_t n = hull.size();
  auto at = [&](std::size_t i) { return points_[static_cast<std::size_t>(hull[i % n])]; };
  // Corners: the hull vertices where it turns; those between two corners lie on one side.
  std::vector<std::size_t> corners;
  for (std::size_t i = 0; i < n; ++i) {
    const PlanPoint &u = at(i + n - 1), &v = at(i), &w = at(i + 1);
    const double lu = std::hypot(v[0] - u[0], v[1] - u[1]),
                 lw = std::hypot(w[0] - v[0], w[1] - v[1]);
    if (orient(u, v, w) > 1e-9 * lu * lw) corners.push_back(i);
  }
  const std::size_t sides = corners.size();
  for (std::size_t s = 0; s < sides; ++s) {
    const std::size_t from = corners[s], to = corners[(s + 1) % sides] + (s + 1 == sides ? n : 0);
    const double tx = at(to)[0] - at(from)[0], ty = at(to)[1] - at(from)[1];
    const int side = static_cast<int>(s);
    for (std::size_t i = from; i < to; ++i) {
      const int u = hull[i % n], w = hull[(i + 1) % n];
      Cell c{Kind::kStrip, {u, w, -1}, {}, {0, 0}, {0, 0}, tx, ty};
      c.sides = {{pairLine(u, w), u > w},  // outside: on the right of u -> w
                 {normalLine(side, tx, ty, u), true},
                 {normalLine(side, tx, ty, w), false}};
      cells_.push_back(std::move(c));
    }
    // The corner at the side's end, between its normal there and the next side's.
    const int v = hull[to % n];
    const std::size_t after = corners[(s + 1) % sides], beyond = corners[(s + 2) % sides];
    const double nx = at(beyond + (beyond <= after ? n : 0))[0] - at(after)[0];
    const double ny = at(beyond + (beyond <= after ? n : 0))[1] - at(after)[1];
    Cell c{Kind::kCorner, {v, -1, -1}, {}, {0, 0}, {0, 0}};
    c.sides = {{normalLine(side, tx, ty, v), true},
               {normalLine(static_cast<int>((s + 1) % sides), nx, ny, v), false}};
    cells_.push_back(std::move(c));
  }
}

PlanPlane PlanPartition::plane(std::size_t c, std::span<const double> z) const {
  const Cell& cell = cells_[c];
  const auto& p = points_;
  const auto i = static_cast<std::size_t>(cell.corner[0]);
  PlanPlane out{p[i][0], p[i][1], z[i], 0.0, 0.0};
  if (cell.kind == Kind::kTriangle) {
    // The plane through the three corners (Cramer's rule on the differences to the first).
    const auto j = static_cast<std::size_t>(cell.corner[1]);
    const auto k = static_cast<std::size_t>(cell.corner[2]);
    const double ux = p[j][0] - p[i][0], uy = p[j][1] - p[i][1], uz = z[j] - z[i];
    const double vx = p[k][0] - p[i][0], vy = p[k][1] - p[i][1], vz = z[k] - z[i];
    const double det = ux * vy - uy * vx;
    out.slope_x = (uz * vy - uy * vz) / det;
    out.slope_y = (ux * vz - uz * vx) / det;
  } else if (cell.kind == Kind::kStrip) {
    // Linear along the side from one point to the next, constant across it.
    const auto j = static_cast<std::size_t>(cell.corner[1]);
    const double run = cell.tx * (p[j][0] - p[i][0]) + cell.ty * (p[j][1] - p[i][1]);
    const double rise = (z[j] - z[i]) / run;
    out.slope_x = rise * cell.tx;
    out.slope_y = rise * cell.ty;
  }
  return out;
}

bool PlanPartition::inside(const Cell& c, double x, double y) const {
  for (const Side& s : c.sides) {
    const double f = lines_[static_cast<std::size_t>(s.line)].at(x, y);
    if (s.closed ? !(f >= 0.0) : !(f < 0.0)) return false;
  }
  return true;
}

std::size_t PlanPartition::cellAt(double x, double y) const {
  for (std::size_t c = 0; c < cells_.size(); ++c) {
    if (inside(cells_[c], x, y)) return c;
  }
  return cells_.size();
}

void PlanPartition::clip(const Cell& c, std::vector<Vec3>& in, std::vector<Vec3>& work) const {
  // Sutherland-Hodgman against each side's half-plane; a crossing point lies on the line, so
  // the cells on both sides of a line share it.
  for (const Side& s : c.sides) {
    const Line& line = lines_[static_cast<std::size_t>(s.line)];
    work.clear();
    const std::size_t n = in.size();
    for (std::size_t k = 0; k < n; ++k) {
      const Vec3& a = in[k];
      const Vec3& b = in[(k + 1) % n];
      const double fa = line.at(a.x(), a.y()), fb = line.at(b.x(), b.y());
      const bool ia = s.closed ? fa >= 0.0 : fa < 0.0, ib = s.closed ? fb >= 0.0 : fb < 0.0;
      if (ia) work.push_back(a);
      if (ia != ib) work.push_back(a + (fa / (fa - fb)) * (b - a));
    }
    in.swap(work);
    if (in.size() < 3) return;
  }
}

PressureResultant PlanPartition::resultant(std::span<const Vec3> points,
                                           std::span<const int> polygon, const Vec3& normal,
                                           std::span<const LinearPressure> pressure) const {
  thread_local std::vector<Vec3> piece, work;
  thread_local std::vector<int> order;
  double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
  for (const int v : polygon) {
    const Vec3& x = points[static_cast<std::size_t>(v)];
    for (int k = 0; k < 2; ++k) lo[k] = std::min(lo[k], x[k]), hi[k] = std::max(hi[k], x[k]);
  }
  PressureResultant out;
  for (std::size_t c = 0; c < cells_.size(); ++c) {
    const Cell& cell = cells_[c];
    if (cell.kind == Kind::kTriangle &&
        (cell.hi[0] < lo[0] || cell.lo[0] > hi[0] || cell.hi[1] < lo[1] || cell.lo[1] > hi[1])) {
      continue;
    }
    piece.clear();
    for (const int v : polygon) piece.push_back(points[static_cast<std::size_t>(v)]);
    clip(cell, piece, work);
    if (piece.size() < 3) continue;
    order.resize(piece.size());
    for (std::size_t k = 0; k < order.size(); ++k) order[k] = static_cast<int>(k);
    const auto r = pressureResultant(piece, order, normal, pressure[c]);
    out.force += r.force;
    out.moment += r.moment;
    out.wetted_area += r.wetted_area;
    out.load += r.load;
  }
  return out;
}

}  // namespace polydem::geometry
