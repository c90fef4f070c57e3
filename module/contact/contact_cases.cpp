#include "polydem/contact/contact_cases.h"

#include <cmath>

namespace polydem::contact {

namespace {

constexpr double kGap = 1e-5;  // penetration of every case

// Square pyramid, base side 1, height 1, apex down at (0,0,-kGap).
std::vector<Vec3> invertedPyramid() {
  const double top = 1.0 - kGap;
  return {{0, 0, -kGap}, {0.5, 0.5, top}, {-0.5, 0.5, top}, {-0.5, -0.5, top}, {0.5, -0.5, top}};
}

// Square pyramid, apex up at the origin, base side 1 at z = -1, turned 45 deg about z.
std::vector<Vec3> uprightPyramidTurned() {
  const double h = std::sqrt(0.5);  // half diagonal of the unit square
  return {{0, 0, 0}, {h, 0, -1}, {0, h, -1}, {-h, 0, -1}, {0, -h, -1}};
}

// Triangular prism with its ridge along x at z = 0 (x in [x0, x1]) and base y in [-.5,.5] at z=-1.
std::vector<Vec3> ridgeAlongX(double x0, double x1) {
  return {{x0, 0, 0}, {x1, 0, 0}, {x0, -0.5, -1}, {x1, -0.5, -1}, {x0, 0.5, -1}, {x1, 0.5, -1}};
}

// The same prism with its ridge along y (y in [-1, 1]) and base x in [-.5,.5].
std::vector<Vec3> ridgeAlongY() {
  return {{0, -1, 0}, {0, 1, 0}, {-0.5, -1, -1}, {-0.5, 1, -1}, {0.5, -1, -1}, {0.5, 1, -1}};
}

// Unit cube turned 45 deg about x, lowest edge along x at z = -kGap, x in [-0.5, 0.5].
std::vector<Vec3> turnedCube() {
  const double h = std::sqrt(0.5);
  std::vector<Vec3> v;
  for (double x : {-0.5, 0.5}) {
    v.push_back({x, 0, -kGap});
    v.push_back({x, h, h - kGap});
    v.push_back({x, -h, h - kGap});
    v.push_back({x, 0, 2 * h - kGap});
  }
  return v;
}

std::vector<Vec3> box(const Vec3& lo, const Vec3& hi) {
  std::vector<Vec3> v;
  for (int i = 0; i < 8; ++i) {
    v.push_back({(i & 1) ? hi.x() : lo.x(), (i & 2) ? hi.y() : lo.y(), (i & 4) ? hi.z() : lo.z()});
  }
  return v;
}

ContactCase make(std::string id, std::string description, std::vector<Vec3> a,
                 std::vector<Vec3> b) {
  return {std::move(id), std::move(description),  std::move(a), std::move(b),
          Vec3(0, 0, 1), Vec3(0, 0, -0.5 * kGap), kGap,         1.0};
}

}  // namespace

std::vector<ContactCase> contactTypeCases() {
  return {
      make("C-VV", "vertex-vertex: inverted pyramid on a pyramid turned 45 deg", invertedPyramid(),
           uprightPyramidTurned()),
      make("C-VE", "vertex-edge: inverted pyramid on a prism ridge", invertedPyramid(),
           ridgeAlongX(-1.0, 1.0)),
      make("C-VF", "vertex-face: inverted pyramid on a box", invertedPyramid(),
           box({-1, -1, -1}, {1, 1, 0})),
      make("C-EEp", "parallel edges: turned cube on an off-centre prism ridge along x",
           turnedCube(), ridgeAlongX(-1.5, 2.5)),
      make("C-EEx", "crossing edges: turned cube on a prism ridge along y", turnedCube(),
           ridgeAlongY()),
      make("C-EF", "edge-face: turned cube on an off-centre box", turnedCube(),
           box({-0.8, -2, -1}, {3.2, 2, 0})),
      make("C-FF", "face-face: cube on an off-centre box",
           box({-0.5, -0.5, -kGap}, {0.5, 0.5, 1 - kGap}), box({-1.2, -1.5, -1}, {2.8, 2.5, 0})),
  };
}

ContactCase transformed(const ContactCase& c, const Mat3& rotation, const Vec3& translation,
                        double scale) {
  ContactCase out = c;
  auto move = [&](const Vec3& x) -> Vec3 { return scale * (rotation * x) + translation; };
  for (auto& v : out.a) v = move(v);
  for (auto& v : out.b) v = move(v);
  out.normal = rotation * c.normal;
  out.point = move(c.point);
  out.depth = scale * c.depth;
  out.size = scale * c.size;
  return out;
}

double angleBetween(const Vec3& u, const Vec3& v) {
  return std::atan2(u.cross(v).norm(), u.dot(v));
}

CaseEvaluation evaluate(const ContactCase& c, const Contact& result) {
  CaseEvaluation e;
  e.touching = result.touching;
  if (!result.touching) return e;
  e.normal_error_rad = angleBetween(result.normal.normalized(), c.normal);
  e.point_error = (result.point - c.point).norm() / c.size;
  const bool potential = result.model == ForceModel::kPotential;
  e.depth_error = potential ? 0.0 : std::abs(result.depth - c.depth) / c.depth;
  e.normal_ok = e.normal_error_rad <= Criteria::kNormalRad;
  e.point_ok = e.point_error <= Criteria::kPointRel;
  e.depth_ok = potential || e.depth_error <= Criteria::kDepthRel;
  return e;
}

}  // namespace polydem::contact
