#include "polydem/contact/face/square_clip.h"

#include <utility>

namespace polydem::contact {

int SquareClipper::clip(const LabelledQuad& a, const LabelledSquare& b, double du2, double dv2,
                        double merge2, std::array<LabelledCorner, kMaxCorners>& out) {
  Working* poly = poly_.data();
  Working* next = next_.data();
  for (int i = 0; i < 4; ++i) {
    poly[i] = {{a.corners[i], feature(FeatureType::kVertex, a.vertex[i]),
                feature(FeatureType::kFace, b.face)},
               i};
  }
  int n = 4;
  // Line k's pass, with k a constant so that the line's distance is one subtraction.
  const auto pass = [&]<int k>() {
    // A corner within the merge distance of line k is put on it (h = 0, kept, no crossing made):
    // where a corner lies on an edge line (aligned equal blocks), the labels and corners are then
    // decided by that tolerance and not by the round-off of h.
    const double side2 = k % 2 == 0 ? dv2 : du2;  // line k's distance is h |V| or h |U|
    int out_count = 0;
    for (int i = 0; i < n; ++i) {
      double hi = squareSide(poly[i].corner.p, k);
      if (hi * hi * side2 <= merge2) {
        hi = 0.0;
        onSquareSide(poly[i].corner.p, k);
      }
      h_[i] = hi;
      out_count += hi < 0.0;
    }
    if (out_count == 0) return true;
    if (out_count == n) {
      n = 0;
      return false;
    }
    if (n + out_count > kMaxCorners) {  // a pass adds at most one corner per outside one
      n = -1;
      return false;
    }
    int kept_count = 0;
    for (int i = 0; i < n; ++i) {
      const int j = i + 1 == n ? 0 : i + 1;
      const double hi = h_[i], hj = h_[j];
      const Working& wi = poly[i];
      if (hi >= 0.0) {
        Working& kept = next[kept_count++];
        kept = wi;
        if (hi == 0.0 && hj < 0.0) kept.carrier = -1 - k;  // leaves along the clip line
      }
      if (!((hi > 0.0 && hj < 0.0) || (hi < 0.0 && hj > 0.0))) continue;
      Working& x = next[kept_count++];
      x.corner.p = wi.corner.p + (hi / (hi - hj)) * (poly[j].corner.p - wi.corner.p);
      onSquareSide(x.corner.p, k);  // the crossing lies on line k: that coordinate is exact
      if (wi.carrier >= 0) {        // an edge of A crosses B's edge k
        x.corner.a = feature(FeatureType::kEdge, a.edge[wi.carrier]);
        x.corner.b = feature(FeatureType::kEdge, b.edge[k]);
        x.corner.side_a = wi.carrier;
        x.corner.side_b = k;
      } else {  // two of the square's lines meet: a vertex of B inside A's face (the corner at
                // the start of line k, or corner 0 for lines 0 and 3; lines that are not adjacent
                // meet outside the square, and a later line cuts that corner away)
        const int previous = -1 - wi.carrier;
        x.corner.a = feature(FeatureType::kFace, a.face);
        x.corner.b = feature(FeatureType::kVertex, b.vertex[previous == 0 && k == 3 ? 0 : k]);
        x.corner.side_a = x.corner.side_b = -1;
      }
      // Entering, the polygon goes on along the crossed edge; leaving, along the clip line.
      x.carrier = hi < 0.0 ? wi.carrier : -1 - k;
    }
    std::swap(poly, next);
    n = kept_count;
    return true;
  };
  if (!(pass.operator()<0>() && pass.operator()<1>() && pass.operator()<2>() &&
        pass.operator()<3>())) {
    return n;  // 0: no overlap; -1: too many corners
  }
  int m = 0;
  for (int i = 0; i < n; ++i) {
    const LabelledCorner& c = poly[i].corner;
    if (m > 0) {
      const Vec2 d = c.p - out[m - 1].p;
      if (du2 * d.x() * d.x() + dv2 * d.y() * d.y() <= merge2) continue;
    }
    out[m++] = c;
  }
  if (m > 1) {
    const Vec2 d = out[0].p - out[m - 1].p;
    if (du2 * d.x() * d.x() + dv2 * d.y() * d.y() <= merge2) --m;
  }
  return m;
}

}  // namespace polydem::contact
