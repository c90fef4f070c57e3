#include "polydem/contact/face/labelled_clip.h"

#include <utility>

#include "polydem/geometry/polygon.h"

namespace polydem::contact {

namespace {

using geometry::cross2;

// The vertex of B where B's edge line `previous` (a line clipped by earlier) meets line `k`.
// Lines are clipped in order, so previous < k; the two are adjacent when k = previous + 1, or
// when they are the last and the first line. Non-adjacent lines meet outside B, and a corner
// there is cut away by a later line; it gets the start of line k as a placeholder label.
int sharedVertex(const LabelledPolygon& b, int previous, int k) {
  const int n = static_cast<int>(b.corners.size());
  if (previous == 0 && k == n - 1) return b.vertex[0];
  return b.vertex[k];
}

// Makes `buffer` hold at least `size` elements; it never shrinks, so once warm this allocates
// nothing.
template <typename T>
void grow(std::vector<T>& buffer, std::size_t size) {
  if (buffer.size() < size) buffer.resize(size);
}

}  // namespace

void LabelledClipper::polygons(const LabelledPolygon& a, const LabelledPolygon& b, double merge,
                               std::vector<LabelledCorner>& out) {
  out.clear();
  const int na = static_cast<int>(a.corners.size()), nb = static_cast<int>(b.corners.size());
  // The working polygons live in buffers that only grow, indexed directly: a pass over n corners
  // writes at most 2 n (every edge keeps its start and adds at most one crossing), so each pass
  // makes room for that first and then writes without a capacity check per corner.
  grow(poly_, static_cast<std::size_t>(na));
  for (int i = 0; i < na; ++i) {
    poly_[i] = {{a.corners[i], feature(FeatureType::kVertex, a.vertex[i]),
                 feature(FeatureType::kFace, b.face)},
                i};
  }
  std::size_t n = static_cast<std::size_t>(na);
  for (int k = 0; k < nb && n > 0; ++k) {
    const Vec2& q0 = b.corners[k];
    const Vec2 d = b.corners[k + 1 < nb ? k + 1 : 0] - q0;
    if (d.squaredNorm() == 0.0) continue;  // a repeated corner carries no line
    grow(h_, n);
    const Working* poly = poly_.data();
    double* h = h_.data();
    std::size_t out_count = 0;  // counted without a branch per corner
    for (std::size_t i = 0; i < n; ++i) {
      h[i] = cross2(d, poly[i].corner.p - q0);  // >= 0: left of the edge, inside B
      out_count += h[i] < 0.0;
    }
    if (out_count == 0) continue;
    if (out_count == n) {
      n = 0;
      break;
    }
    grow(next_, 2 * n);
    Working* next = next_.data();
    std::size_t kept_count = 0;
    for (std::size_t i = 0; i < n; ++i) {
      const std::size_t j = i + 1 == n ? 0 : i + 1;
      const double hi = h[i], hj = h[j];
      const Working& wi = poly[i];
      if (hi >= 0.0) {
        Working& kept = next[kept_count++];
        kept = wi;
        if (hi == 0.0 && hj < 0.0) kept.carrier = -1 - k;  // leaves along the clip line
      }
      if (!((hi > 0.0 && hj < 0.0) || (hi < 0.0 && hj > 0.0))) continue;
      Working& x = next[kept_count++];
      x.corner.p = wi.corner.p + (hi / (hi - hj)) * (poly[j].corner.p - wi.corner.p);
      if (wi.carrier >= 0) {  // an edge of A crosses B's edge k
        x.corner.a = feature(FeatureType::kEdge, a.edge[wi.carrier]);
        x.corner.b = feature(FeatureType::kEdge, b.edge[k]);
        x.corner.side_a = wi.carrier;
        x.corner.side_b = k;
      } else {  // two of B's edge lines meet: a vertex of B inside A's face
        x.corner.a = feature(FeatureType::kFace, a.face);
        x.corner.b = feature(FeatureType::kVertex, sharedVertex(b, -1 - wi.carrier, k));
        x.corner.side_a = x.corner.side_b = -1;
      }
      // Entering, the polygon goes on along the crossed edge; leaving, along the clip line.
      x.carrier = hi < 0.0 ? wi.carrier : -1 - k;
    }
    std::swap(poly_, next_);
    n = kept_count;
  }
  const double merge2 = merge * merge;
  for (std::size_t i = 0; i < n; ++i) {
    const LabelledCorner& c = poly_[i].corner;
    if (!out.empty() && (c.p - out.back().p).squaredNorm() <= merge2) continue;
    out.push_back(c);
  }
  if (out.size() > 1 && (out.front().p - out.back().p).squaredNorm() <= merge2) out.pop_back();
}

void LabelledClipper::segment(const Vec2& s0, const Vec2& s1, int v0, int v1, int edge,
                              bool segment_is_a, const LabelledPolygon& polygon,
                              std::vector<LabelledCorner>& out) {
  out.clear();
  const int n = static_cast<int>(polygon.corners.size());
  double t_lo = 0.0, t_hi = 1.0;
  int k_lo = -1, k_hi = -1;  // the polygon edge that cut each end (-1: the end is inside)
  for (int k = 0; k < n; ++k) {
    const Vec2& q0 = polygon.corners[k];
    const Vec2 d = polygon.corners[(k + 1) % n] - q0;
    if (d.squaredNorm() == 0.0) continue;
    const double h0 = cross2(d, s0 - q0), h1 = cross2(d, s1 - q0);  // >= 0 inside
    if (h0 < 0.0 && h1 < 0.0) return;
    if (h0 < 0.0) {
      const double t = h0 / (h0 - h1);
      if (t > t_lo) t_lo = t, k_lo = k;
    } else if (h1 < 0.0) {
      const double t = h0 / (h0 - h1);
      if (t < t_hi) t_hi = t, k_hi = k;
    }
  }
  if (!(t_lo < t_hi)) return;
  auto corner = [&](double t, int k, int vertex) {
    LabelledCorner c;
    c.p = s0 + t * (s1 - s0);
    const std::uint32_t own =
        k < 0 ? feature(FeatureType::kVertex, vertex) : feature(FeatureType::kEdge, edge);
    const std::uint32_t other = k < 0 ? feature(FeatureType::kFace, polygon.face)
                                      : feature(FeatureType::kEdge, polygon.edge[k]);
    c.a = segment_is_a ? own : other;
    c.b = segment_is_a ? other : own;
    return c;
  };
  out.push_back(corner(t_lo, k_lo, v0));
  out.push_back(corner(t_hi, k_hi, v1));
}

}  // namespace polydem::contact
