// Support walks, closest-vertex bands and plane helpers of the FCP (see fcp_detail.h).
#include <algorithm>
#include <cmath>

#include "contact/fcp_detail.h"

namespace polydem::contact::fcp_detail {

Extreme climbMax(const Body& body, const Vec3& d, int hint) {
  const auto& neighbours = body.shape->vertexNeighbours();
  const Vec3* v = body.vertices.data();
  Extreme best{hint, d.dot(v[hint])};
  for (;;) {
    Extreme next = best;
    for (int u : neighbours[best.index]) {
      const double value = d.dot(v[u]);
      if (value > next.value) next = {u, value};
    }
    if (next.index == best.index) return best;
    best = next;
  }
}

Extreme supportMax(const Body& body, const Vec3& d) {
  // Up to this many vertices a scan is as cheap as a climb from an arbitrary start.
  constexpr int kScanVertices = 32;
  const int n = static_cast<int>(body.vertices.size());
  if (n > kScanVertices) return climbMax(body, d, 0);
  Extreme best{0, d.dot(body.vertices[0])};
  for (int i = 1; i < n; ++i) {
    const double value = d.dot(body.vertices[i]);
    if (value > best.value) best = {i, value};
  }
  return best;
}

Extreme collectBand(const Body& body, const Vec3& d, int seed, double threshold,
                    std::vector<int>& out) {
  const auto& neighbours = body.shape->vertexNeighbours();
  const Vec3* v = body.vertices.data();
  out.clear();
  out.push_back(seed);
  Extreme top{seed, d.dot(v[seed])};
  // `out` doubles as the work list: entries past `next` have not had their neighbours visited.
  for (std::size_t next = 0; next < out.size(); ++next) {
    for (int u : neighbours[out[next]]) {
      if (std::find(out.begin(), out.end(), u) != out.end()) continue;
      const double value = d.dot(v[u]);
      if (value >= threshold) {
        out.push_back(u);
        if (value > top.value) top = {u, value};
      }
    }
  }
  return top;
}

int convexOrder(std::span<const Vec3> points, const geometry::PlaneFrame& frame,
                std::vector<int>& order) {
  // Andrew's monotone chain on the projected points (a handful: the closest vertices).
  const int n = static_cast<int>(points.size());
  thread_local std::vector<std::pair<Vec2, int>> sorted;
  sorted.clear();
  for (int i = 0; i < n; ++i) sorted.emplace_back(frame.project(points[i]), i);
  std::sort(sorted.begin(), sorted.end(), [](const auto& p, const auto& q) {
    return p.first.x() < q.first.x() || (p.first.x() == q.first.x() && p.first.y() < q.first.y());
  });
  const auto turn = [&](int i, int j, int k) {
    const Vec2 u = sorted[j].first - sorted[i].first, w = sorted[k].first - sorted[i].first;
    return u.x() * w.y() - u.y() * w.x();
  };
  thread_local std::vector<int> hull;
  hull.assign(2 * static_cast<std::size_t>(n) + 1, 0);
  int k = 0;
  for (int i = 0; i < n; ++i) {  // lower chain
    while (k >= 2 && turn(hull[k - 2], hull[k - 1], i) <= 0.0) --k;
    hull[k++] = i;
  }
  for (int i = n - 2, lower = k + 1; i >= 0; --i) {  // upper chain
    while (k >= lower && turn(hull[k - 2], hull[k - 1], i) <= 0.0) --k;
    hull[k++] = i;
  }
  const int count = n == 1 ? 1 : k - 1;  // the last point repeats the first
  order.clear();
  for (int i = 0; i < count; ++i) order.push_back(sorted[hull[i]].second);
  return count;
}

}  // namespace polydem::contact::fcp_detail
