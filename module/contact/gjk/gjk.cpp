#include "polydem/contact/gjk/gjk.h"

#include <cmath>

namespace polydem::contact {

namespace {

/// Closest point of a sub-simplex to the origin and the simplex vertices that span it.
struct Closest {
  Vec3 point;
  int count = 0;
  int index[3] = {0, 0, 0};
};

Closest onSegment(const Simplex& s, int i, int j) {
  const Vec3& a = s.p[i].w;
  const Vec3& b = s.p[j].w;
  const Vec3 ab = b - a;
  const double t = -a.dot(ab);
  if (t <= 0.0) return {a, 1, {i}};
  const double length2 = ab.squaredNorm();
  if (t >= length2) return {b, 1, {j}};
  return {a + (t / length2) * ab, 2, {i, j}};
}

/// Ericson, Real-Time Collision Detection, 5.1.5, with the query point at the origin: the Voronoi
/// region of the origin from dot products relative to the vertices.
Closest onTriangle(const Simplex& s, int i, int j, int k) {
  const Vec3& a = s.p[i].w;
  const Vec3& b = s.p[j].w;
  const Vec3& c = s.p[k].w;
  const Vec3 ab = b - a, ac = c - a;
  const double d1 = -ab.dot(a), d2 = -ac.dot(a);
  if (d1 <= 0.0 && d2 <= 0.0) return {a, 1, {i}};
  const double d3 = -ab.dot(b), d4 = -ac.dot(b);
  if (d3 >= 0.0 && d4 <= d3) return {b, 1, {j}};
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) return {a + (d1 / (d1 - d3)) * ab, 2, {i, j}};
  const double d5 = -ab.dot(c), d6 = -ac.dot(c);
  if (d6 >= 0.0 && d5 <= d6) return {c, 1, {k}};
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) return {a + (d2 / (d2 - d6)) * ac, 2, {i, k}};
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0) {
    const double t = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return {b + t * (c - b), 2, {j, k}};
  }
  const double sum = va + vb + vc;
  if (!(sum > 0.0)) {
    // A triangle flat to round-off: its closest point is on one of its edges.
    Closest best = onSegment(s, i, j);
    for (const Closest& e : {onSegment(s, i, k), onSegment(s, j, k)}) {
      if (e.point.squaredNorm() < best.point.squaredNorm()) best = e;
    }
    return best;
  }
  return {a + (vb / sum) * ab + (vc / sum) * ac, 3, {i, j, k}};
}

/// Whether the origin and vertex `d` lie strictly on opposite sides of the plane of (a, b, c).
bool originBeyond(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  const Vec3 n = (b - a).cross(c - a);
  const double origin_side = -n.dot(a);
  const double d_side = n.dot(d - a);
  return (origin_side > 0.0 && d_side < 0.0) || (origin_side < 0.0 && d_side > 0.0);
}

/// Keeps the vertices c.index (increasing, so compacting in place reads ahead of writes).
void keep(Simplex& s, const Closest& c) {
  for (int m = 0; m < c.count; ++m) s.p[m] = s.p[c.index[m]];
  s.size = c.count;
}

}  // namespace

bool closestToOrigin(Simplex& s, Vec3& v) {
  Closest c;
  switch (s.size) {
    case 1:
      v = s.p[0].w;
      return false;
    case 2:
      c = onSegment(s, 0, 1);
      break;
    case 3:
      c = onTriangle(s, 0, 1, 2);
      break;
    default: {
      const Vec3& p0 = s.p[0].w;
      const Vec3& p1 = s.p[1].w;
      const Vec3& p2 = s.p[2].w;
      const Vec3& p3 = s.p[3].w;
      // Signed volume of the tetrahedron; a flat one (to round-off relative to its edges) never
      // contains the origin, its faces are searched instead.
      const Vec3 e1 = p1 - p0, e2 = p2 - p0, e3 = p3 - p0;
      const double volume = e1.dot(e2.cross(e3));
      const double edges2 = e1.squaredNorm() * e2.squaredNorm() * e3.squaredNorm();
      const bool flat = !(volume * volume > 1e-28 * edges2);  // |volume| > 1e-14 |e1||e2||e3|
      static constexpr int kFaces[4][4] = {{0, 1, 2, 3}, {0, 1, 3, 2}, {0, 2, 3, 1}, {1, 2, 3, 0}};
      bool found = false;
      for (const auto& f : kFaces) {
        const Vec3& a = s.p[f[0]].w;
        const Vec3& b = s.p[f[1]].w;
        const Vec3& cc = s.p[f[2]].w;
        if (!flat && !originBeyond(a, b, cc, s.p[f[3]].w)) continue;
        const Closest candidate = onTriangle(s, f[0], f[1], f[2]);
        if (!found || candidate.point.squaredNorm() < c.point.squaredNorm()) c = candidate;
        found = true;
      }
      if (!found) {
        v = Vec3::Zero();
        return true;
      }
      break;
    }
  }
  v = c.point;
  keep(s, c);
  return false;
}

GjkResult gjkIntersect(MinkowskiSupport& support, const Vec3& initial_axis, double tolerance) {
  GjkResult r;
  const Vec3 axis = initial_axis.squaredNorm() > 0.0 ? initial_axis : Vec3::UnitX();
  Simplex& s = r.simplex;
  // The point of A - B lowest along the axis: if it is above the origin, the axis separates.
  s.p[0] = support(-axis);
  s.size = 1;
  if (axis.dot(s.p[0].w) > 0.0) {
    r.separated = true;
    r.axis = axis.normalized();
    return r;
  }
  Vec3 v = s.p[0].w;
  const double tolerance2 = tolerance * tolerance;
  for (int it = 1; it <= kGjkMaxIterations; ++it) {
    r.iterations = it;
    if (v.squaredNorm() <= tolerance2) return r;  // the origin is on the simplex
    const SupportPoint w = support(-v);
    // Van den Bergen 2001: min over A - B of v . x > 0 means v separates.
    if (v.dot(w.w) > 0.0) {
      r.separated = true;
      r.axis = v.normalized();
      return r;
    }
    // Without round-off a repeated vertex cannot occur here (it would satisfy v . w = v . v > 0):
    // it means no progress is possible, the origin is as close to the simplex as it gets.
    for (int m = 0; m < s.size; ++m) {
      if (s.p[m].ia == w.ia && s.p[m].ib == w.ib) return r;
    }
    s.p[s.size++] = w;
    if (closestToOrigin(s, v)) return r;
  }
  r.converged = false;
  return r;
}

}  // namespace polydem::contact
