// Mass properties (unit density) and the circumscribed and inscribed spheres.
//
// Volume, centroid and inertia come from an exact decomposition of the solid: every face is split
// into a fan of triangles from its first vertex, and every triangle spans a tetrahedron with a
// reference point. The signed tetrahedra add up to the solid whatever the reference point (the
// divergence theorem in discrete form), and each tetrahedron's moments have closed forms:
//   V = det[a b c] / 6,   first moment V (a + b + c) / 4,
//   second moment  int x x^T dV = det[a b c] / 120 (a a^T + b b^T + c c^T + s s^T),  s = a + b + c,
// for a tetrahedron with one vertex at the origin and the others at a, b, c: the moments
// (1 + delta_ij) / 120 of the unit tetrahedron mapped by the matrix [a b c]. The sums go through
// ExactSum so that mirror-symmetric shapes have exactly symmetric moments (a box centred at the
// origin has its centroid exactly there) and the result does not depend on the order of the faces.
#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <vector>

#include "polydem/core/error.h"
#include "polydem/core/exact_sum.h"
#include "polydem/core/strings.h"
#include "polydem/geometry/convex_polyhedron.h"
#include "polydem/geometry/small_lp.h"

namespace polydem::geometry {

namespace {

/// Calls f(a, b, c) for every triangle of the fan decomposition of the surface.
template <class F>
void forEachTriangle(const std::vector<Face>& faces, const std::vector<Vec3>& vertices, F&& f) {
  for (const Face& face : faces) {
    const Vec3& a = vertices[face.vertices[0]];
    for (std::size_t k = 1; k + 1 < face.vertices.size(); ++k) {
      f(a, vertices[face.vertices[k]], vertices[face.vertices[k + 1]]);
    }
  }
}

}  // namespace

void ConvexPolyhedron::computeMassProperties() {
  // Pass 1: volume and centroid, tetrahedra apexed at the centre of the bounding box.
  Vec3 lo = vertices_[0], hi = vertices_[0];
  for (const Vec3& v : vertices_) {
    lo = lo.cwiseMin(v);
    hi = hi.cwiseMax(v);
  }
  const Vec3 ref = 0.5 * (lo + hi);
  ExactSum six_volume;
  std::array<ExactSum, 3> twentyfour_moment;
  forEachTriangle(faces_, vertices_, [&](const Vec3& pa, const Vec3& pb, const Vec3& pc) {
    const Vec3 a = pa - ref, b = pb - ref, c = pc - ref;
    const double det = a.dot(b.cross(c));
    six_volume += det;
    const Vec3 s = a + b + c;
    for (int i = 0; i < 3; ++i) twentyfour_moment[i] += det * s[i];
  });
  const double six_v = six_volume.value();
  if (!(six_v > 0.0)) {
    throw GeometryError(cat("polyhedron has no positive volume (6V = ", six_v, ")"));
  }
  volume_ = six_v / 6.0;
  for (int i = 0; i < 3; ++i) centroid_[i] = ref[i] + twentyfour_moment[i].value() / (4.0 * six_v);

  // Pass 2: second moments about the centroid itself, so no parallel-axis cancellation.
  std::array<ExactSum, 6> c120;  // 120 * int x x^T dV: xx, yy, zz, xy, xz, yz
  forEachTriangle(faces_, vertices_, [&](const Vec3& pa, const Vec3& pb, const Vec3& pc) {
    const Vec3 a = pa - centroid_, b = pb - centroid_, c = pc - centroid_;
    const double det = a.dot(b.cross(c));
    const Vec3 s = a + b + c;
    const auto m = [&](int i, int j) {
      return a[i] * a[j] + b[i] * b[j] + c[i] * c[j] + s[i] * s[j];
    };
    c120[0] += det * m(0, 0);
    c120[1] += det * m(1, 1);
    c120[2] += det * m(2, 2);
    c120[3] += det * m(0, 1);
    c120[4] += det * m(0, 2);
    c120[5] += det * m(1, 2);
  });
  Mat3 second;
  second(0, 0) = c120[0].value() / 120.0;
  second(1, 1) = c120[1].value() / 120.0;
  second(2, 2) = c120[2].value() / 120.0;
  second(0, 1) = second(1, 0) = c120[3].value() / 120.0;
  second(0, 2) = second(2, 0) = c120[4].value() / 120.0;
  second(1, 2) = second(2, 1) = c120[5].value() / 120.0;
  inertia_ = second.trace() * Mat3::Identity() - second;
}

void ConvexPolyhedron::computeRadii() {
  circumradius_ = 0.0;
  for (const Vec3& v : vertices_) circumradius_ = std::max(circumradius_, (v - centroid_).norm());

  // Chebyshev centre of the face planes: maximise r s.t. n_i . x + r <= d_i. Unknowns scaled to
  // the shape, x = centroid + L y and r = L rho with L the circumradius, so |rows|, |b| ~ 1.
  const double length = circumradius_;
  std::vector<Vec4> rows(faces_.size());
  std::vector<double> b(faces_.size());
  for (std::size_t i = 0; i < faces_.size(); ++i) {
    const Face& face = faces_[i];
    rows[i] << face.normal, 1.0;
    b[i] = (face.offset - face.normal.dot(centroid_)) / length;
  }
  const SmallLpResult lp = solveSmallLp(rows, b, Vec4(0.0, 0.0, 0.0, -1.0));
  // The radius is measured at the centre found rather than read off the LP, so the sphere is
  // inscribed to round-off whatever the LP's tolerances did. On extremely thin shapes (thickness
  // below ~1e-9 of the size) the LP loses accuracy or gives up; the centroid, always at least a
  // quarter of the thickness from every face, is then the fallback centre.
  const auto clearance = [&](const Vec3& x) {
    double r = std::numeric_limits<double>::infinity();
    for (const Face& face : faces_) r = std::min(r, face.offset - face.normal.dot(x));
    return r;
  };
  incenter_ = centroid_;
  inradius_ = clearance(centroid_);
  if (lp.status == SmallLpResult::Status::kOptimal) {
    const Vec3 centre = centroid_ + length * lp.z.head<3>();
    const double r = clearance(centre);
    if (r > inradius_) {
      incenter_ = centre;
      inradius_ = r;
    }
  }
  if (!(inradius_ > 0.0)) {
    throw GeometryError(cat("inscribed sphere: the centroid is not inside the ", faces_.size(),
                            " face planes (clearance ", inradius_, ")"));
  }
}

}  // namespace polydem::geometry
