// A sweep triangulation made Delaunay by flips (plan_triangulation.h).
#include "polydem/geometry/plan_triangulation.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <utility>

#include "polydem/core/strings.h"

namespace polydem::geometry {

namespace {

// > 0 when d lies inside the circle through the counter-clockwise a, b, c.
double inCircle(const PlanPoint& a, const PlanPoint& b, const PlanPoint& c, const PlanPoint& d) {
  const double ax = a[0] - d[0], ay = a[1] - d[1], bx = b[0] - d[0], by = b[1] - d[1];
  const double cx = c[0] - d[0], cy = c[1] - d[1];
  const double a2 = ax * ax + ay * ay, b2 = bx * bx + by * by, c2 = cx * cx + cy * cy;
  return ax * (by * c2 - b2 * cy) - ay * (bx * c2 - b2 * cx) + a2 * (bx * cy - by * cx);
}

// Joins the sorted points one by one to the hull edges each sees (strictly); `hull` is kept
// counter-clockwise. The first points, while they lie on one line, form a chain.
std::string sweep(std::span<const PlanPoint> p, const std::vector<int>& order,
                  std::vector<PlanTriangle>& out) {
  std::size_t k = 2;
  while (k < order.size() && orient(p[order[0]], p[order[1]], p[order[k]]) == 0.0) ++k;
  const int apex = order[k];
  const bool left = orient(p[order[0]], p[order[1]], p[apex]) > 0.0;
  std::vector<int> hull;
  for (std::size_t i = 0; i < k; ++i) hull.push_back(order[left ? i : k - 1 - i]);
  for (std::size_t i = 0; i + 1 < k; ++i) out.push_back({hull[i], hull[i + 1], apex});
  hull.push_back(apex);
  for (std::size_t j = k + 1; j < order.size(); ++j) {
    const int q = order[j];
    const std::size_t n = hull.size();
    std::vector<char> sees(n);
    for (std::size_t i = 0; i < n; ++i)
      sees[i] = orient(p[hull[i]], p[hull[(i + 1) % n]], p[q]) < 0;
    std::size_t first = n;
    for (std::size_t i = 0; i < n; ++i) {
      if (sees[i] && !sees[(i + n - 1) % n]) first = i;
    }
    if (first == n) return cat("point ", q + 1, " lies on a line with the points before it");
    std::size_t last = first;
    while (sees[(last + 1) % n]) last = (last + 1) % n;
    // The visible chain hull[first] .. hull[last + 1] gets a triangle per edge; its inner
    // vertices leave the hull.
    std::vector<int> next{q};
    for (std::size_t i = first;; i = (i + 1) % n) {
      out.push_back({hull[(i + 1) % n], hull[i], q});
      if (i == last) break;
    }
    for (std::size_t i = (last + 1) % n;; i = (i + 1) % n) {
      next.push_back(hull[i]);
      if (i == first) break;
    }
    hull = std::move(next);
  }
  return "";
}

// One pass of Lawson's flips over the edges shared by two triangles: the diagonal of the two is
// flipped where the fourth point lies inside the circumcircle by more than `tolerance`; a
// triangle flipped in this pass waits for the next. Returns the number of flips.
int flipPass(std::span<const PlanPoint> p, std::vector<PlanTriangle>& t, double tolerance) {
  std::map<std::pair<int, int>, std::pair<int, int>> edges;  // (a, b) -> (triangle, corner c)
  for (std::size_t i = 0; i < t.size(); ++i) {
    for (int e = 0; e < 3; ++e) {
      edges[{t[i][e], t[i][(e + 1) % 3]}] = {static_cast<int>(i), (e + 2) % 3};
    }
  }
  std::vector<char> changed(t.size(), 0);
  int flips = 0;
  for (const auto& [edge, tri] : edges) {
    const auto [a, b] = edge;
    if (a > b) continue;  // each shared edge once
    const auto other = edges.find({b, a});
    if (other == edges.end()) continue;
    const int t1 = tri.first, t2 = other->second.first;
    if (changed[t1] || changed[t2]) continue;
    const int c = t[t1][tri.second], d = t[t2][other->second.second];
    if (!(inCircle(p[a], p[b], p[c], p[d]) > tolerance)) continue;
    t[t1] = {a, d, c};
    t[t2] = {d, b, c};
    changed[t1] = changed[t2] = 1;
    ++flips;
  }
  return flips;
}

}  // namespace

PlanTriangulation delaunayTriangulation(std::span<const PlanPoint> p) {
  PlanTriangulation out;
  const int n = static_cast<int>(p.size());
  if (n < 3) {
    out.error = cat("needs at least three points, got ", n);
    return out;
  }
  double lo[2] = {p[0][0], p[0][1]}, hi[2] = {p[0][0], p[0][1]};
  for (const auto& q : p) {
    for (int k = 0; k < 2; ++k) lo[k] = std::min(lo[k], q[k]), hi[k] = std::max(hi[k], q[k]);
  }
  const double extent = std::max(hi[0] - lo[0], hi[1] - lo[1]);
  for (int i = 0; i < n; ++i) {
    for (int j = i + 1; j < n; ++j) {
      if (std::hypot(p[i][0] - p[j][0], p[i][1] - p[j][1]) <= 1e-9 * extent) {
        out.error = cat("points ", i + 1, " and ", j + 1, " lie at one place in plan (x, y)");
        return out;
      }
    }
  }
  std::vector<int> order(static_cast<std::size_t>(n));
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](int a, int b) { return p[a] < p[b]; });
  // Not all on one line: some point stands off the line through the first and the farthest.
  const PlanPoint& a = p[order[0]];
  const PlanPoint& b = p[order[static_cast<std::size_t>(n - 1)]];
  double off = 0.0;
  for (const auto& q : p) off = std::max(off, std::abs(orient(a, b, q)));
  if (!(off > 1e-9 * extent * extent)) {
    out.error = "the points lie on one line in plan (x, y): they give no surface";
    return out;
  }
  out.error = sweep(p, order, out.triangles);
  if (!out.error.empty()) return out;
  const double tolerance = 1e-10 * std::pow(extent, 4);
  for (int pass = 0; pass < 4 * n * n && flipPass(p, out.triangles, tolerance) > 0; ++pass) {
  }
  return out;
}

}  // namespace polydem::geometry
