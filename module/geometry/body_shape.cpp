#include "polydem/geometry/body_shape.h"

#include <Eigen/Eigenvalues>
#include <cmath>

namespace polydem::geometry {

namespace {

/// Inertia tensors whose off-diagonal terms (or eigenvalue gaps) are below this fraction of the
/// largest moment are treated as diagonal (or as having a repeated eigenvalue).
constexpr double kRelDiagonal = 1e-12;

/// Flips v so that its largest component (the first of equal ones) is positive.
Vec3 signFixed(const Vec3& v) {
  int k = 0;
  for (int i = 1; i < 3; ++i) {
    if (std::abs(v[i]) > std::abs(v[k])) k = i;
  }
  return v[k] < 0.0 ? Vec3(-v) : v;
}

/// The unit vector perpendicular to `axis` closest to a coordinate axis (the coordinate axis most
/// perpendicular to `axis`, the first of equal ones, projected).
Vec3 perpendicularNearCoordinateAxis(const Vec3& axis) {
  int k = 0;
  for (int i = 1; i < 3; ++i) {
    if (std::abs(axis[i]) < std::abs(axis[k])) k = i;
  }
  const Vec3 e = Vec3::Unit(k);
  return (e - axis[k] * axis).normalized();
}

/// Principal axes as the columns of a proper rotation, moments ascending. Repeated moments leave
/// a plane (or all of space) of principal axes: the choice then stays near the input axes.
Mat3 principalAxes(const Mat3& inertia) {
  const Eigen::SelfAdjointEigenSolver<Mat3> eig(inertia);
  const Vec3 m = eig.eigenvalues();
  const Mat3 e = eig.eigenvectors();
  const double tol = kRelDiagonal * m.cwiseAbs().maxCoeff();
  Mat3 r;
  if (m[2] - m[0] <= tol) return Mat3::Identity();  // isotropic: every frame is principal
  if (m[1] - m[0] <= tol) {                         // smallest moment repeated
    const Vec3 u = signFixed(e.col(2));
    const Vec3 p = perpendicularNearCoordinateAxis(u);
    r << p, u.cross(p), u;
  } else if (m[2] - m[1] <= tol) {  // largest moment repeated
    const Vec3 u = signFixed(e.col(0));
    const Vec3 p = perpendicularNearCoordinateAxis(u);
    r << u, p, u.cross(p);
  } else {
    const Vec3 a = signFixed(e.col(0));
    const Vec3 b = signFixed(e.col(1));
    r << a, b, a.cross(b);
  }
  return r;
}

}  // namespace

BodyFrameResult toBodyFrame(const ConvexPolyhedron& input, std::string name) {
  const Mat3& inertia = input.inertia();
  const double largest = inertia.diagonal().cwiseAbs().maxCoeff();
  const double off_diagonal =
      std::max({std::abs(inertia(0, 1)), std::abs(inertia(0, 2)), std::abs(inertia(1, 2))});
  const Mat3 r = off_diagonal <= kRelDiagonal * largest ? Mat3::Identity() : principalAxes(inertia);

  BodyFrameResult out;
  out.centroid = input.centroid();
  out.rotation = Quat(r).normalized();
  // Translate first (exact per coordinate up to one rounding), then rotate about the origin.
  ConvexPolyhedron body = input.transformed(Mat3::Identity(), -out.centroid);
  if (r != Mat3::Identity()) body = body.transformed(r.transpose(), Vec3::Zero());

  BodyShape& shape = out.shape;
  shape.name = std::move(name);
  shape.volume = body.volume();
  shape.principal_moments = body.inertia().diagonal();
  shape.circumradius = body.circumradius();
  shape.inradius = body.inradius();
  shape.polyhedron = std::make_shared<const ConvexPolyhedron>(std::move(body));
  return out;
}

}  // namespace polydem::geometry
