// Support walks, closest-vertex bands and plane helpers of the FCP (see fcp_detail.h).
#include <algorithm>
#include <cmath>

#include "polydem/contact/fcp/fcp_detail.h"

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

EdgeCone edgeCone(const Body& body, int e, const Vec3& u0, const Vec3& u1) {
  const geometry::Edge& edge = body.shape->edges()[e];
  EdgeCone c;
  const Vec3 w = u0.cross(u1);
  c.p = u1.cross(w);
  c.q = w.cross(u0);
  c.scale = w.norm();
  c.dir = body.vertices[edge.v1] - body.vertices[edge.v0];
  c.length = c.dir.norm();
  c.point = body.vertices[edge.v0];
  c.v0 = edge.v0;
  return c;
}

EdgeCone edgeCone(const Body& body, int e) {
  const geometry::Edge& edge = body.shape->edges()[e];
  return edgeCone(body, e, body.faceNormal(edge.f0), body.faceNormal(edge.f1));
}

void worldNormals(const Body& body, std::vector<Vec3>& out) {
  const auto& faces = body.shape->faces();
  out.resize(faces.size());
  for (std::size_t f = 0; f < faces.size(); ++f) out[f] = body.rotation * faces[f].normal;
}

double maxOverArc(const Vec3& u0, const Vec3& u1, const Vec3& x) {
  // x's projection on the arc's plane is s u0 + t u1; inside the cone when s, t >= 0.
  const double a0 = x.dot(u0), a1 = x.dot(u1), c = u0.dot(u1);
  const double det = 1.0 - c * c;
  if (det < 1e-12) return x.norm();  // nearly coplanar faces: |x| bounds it safely
  if (a0 - c * a1 >= 0.0 && a1 - c * a0 >= 0.0) {
    return std::sqrt(std::max(0.0, (a0 * a0 + a1 * a1 - 2.0 * c * a0 * a1) / det));
  }
  return std::max(a0, a1);
}

int coneSide(const EdgeCone& e, const Vec3& c, double c_norm2) {
  // Slack, as a sine: arcs touching at an end still count as crossing.
  constexpr double kConeSlack = 1e-12;
  const double s = c.dot(e.p), t = c.dot(e.q);
  if (s >= 0.0 && t >= 0.0) return 1;
  if (s <= 0.0 && t <= 0.0) return -1;
  const double tol = kConeSlack * std::sqrt(c_norm2) * e.scale;
  if (s >= -tol && t >= -tol) return 1;
  if (s <= tol && t <= tol) return -1;
  return 0;
}

int edgeBetween(const Body& body, int v0, int v1) {
  const auto& neighbours = body.shape->vertexNeighbours()[v0];
  for (std::size_t k = 0; k < neighbours.size(); ++k) {
    if (neighbours[k] == v1) return body.shape->vertexEdges()[v0][k];
  }
  return -1;
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
