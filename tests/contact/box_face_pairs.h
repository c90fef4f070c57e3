// Face pairs of rectangular boxes shared by the builder's comparison tests
// (face_contact_box_test.cpp, face_contact_reference_test.cpp): the shapes and the aligned
// configurations whose corners lie exactly on the other face's edge lines, where a clip's labels
// are decided by zero or round-off-sized distances.
#pragma once

#include <cmath>
#include <numbers>
#include <random>

#include "contact_test_util.h"
#include "polydem/contact/contact.h"
#include "polydem/contact/support.h"
#include "polydem/geometry/shapes.h"

namespace polydem::contact::testing {

inline Mat3 about(const Vec3& axis, double angle) {
  return Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix();
}

inline geometry::ConvexPolyhedron boxShape(const Vec3& half) {
  return geometry::ConvexPolyhedron::fromPoints(geometry::shapes::boxAround(Vec3::Zero(), half));
}

/// Calls visit(a, b, contact, size, reach) for box A pressed 1e-3 of its side onto the top face
/// of a cube B: equal squares shifted by exact binary fractions of their side, boxes of half or
/// 3/4 the side sharing an edge line, shifts of 1e-3 and 1e-12 of the side; in place, scaled,
/// turned and moved 500 sizes away. `reach` bounds the points' distance from the origin. Stops
/// when visit() returns false.
template <class Visit>
void forEachDegenerateBoxFacePair(std::mt19937_64& rng, Visit&& visit) {
  const double shifts[] = {0.0, 0.25, 0.5, -0.5, 0.125, 1e-3, -1e-3, 1e-12};
  for (const Vec3& half_a : {Vec3(0.5, 0.5, 0.5), Vec3(0.25, 0.5, 0.5), Vec3(0.5, 0.375, 0.5)}) {
    for (double sx : shifts) {
      for (double sy : shifts) {
        for (int motion = 0; motion < 4; ++motion) {
          const double scale = motion == 0 ? 1.0 : std::pow(10.0, -3.0 + 2.0 * motion);
          const Mat3 turn = motion < 2 ? Mat3::Identity() : randomRotation(rng);
          const Vec3 shift = motion == 3 ? Vec3(500.0 * scale * randomUnit(rng)) : Vec3::Zero();
          const Vec3 xa(sx, sy, 1.0 - 1e-3 - (0.5 - half_a.z()));
          Placed a(boxShape(scale * half_a), shift + scale * (turn * xa), turn);
          Placed b(boxShape(scale * Vec3(0.5, 0.5, 0.5)), shift, turn);
          Contact c;
          c.touching = true;
          c.normal = turn * Vec3::UnitZ();
          c.point = shift + scale * (turn * Vec3(0.5 * sx, 0.5 * sy, 0.5));
          c.depth = scale * 1e-3;
          const double size = pairLengthScale(a.body(), b.body());
          if (!visit(a.body(), b.body(), c, size, shift.norm() + 2.0 * size)) return;
        }
      }
    }
  }
}

/// Places face `ia` of shape `sa` onto face `ib` of `sb` and calls visit(a, b, contact, size,
/// reach): B's face at z = 0 looking up, A's looking down, A turned about z by `spin`, tilted
/// about `tilt_axis` by `tilt`, slid in the plane by `slide` and sunk by `depth`; then the whole
/// pair scaled by `scale`, turned by `turn` and moved by `shift`. The contact normal is B's face
/// normal (+z before the motion), the point the slide; `reach` bounds the points' distance from
/// the origin.
template <class Visit>
void placeFaceOnFace(const geometry::ConvexPolyhedron& sa, const geometry::ConvexPolyhedron& sb,
                     int ia, int ib, double spin, const Vec3& tilt_axis, double tilt,
                     const Vec2& slide, double depth, double scale, const Mat3& turn,
                     const Vec3& shift, Visit&& visit) {
  const auto& fa = sa.faces()[ia];
  const auto& fb = sb.faces()[ib];
  const Mat3 rb = Eigen::Quaterniond::FromTwoVectors(fb.normal, Vec3::UnitZ()).toRotationMatrix();
  const Mat3 ra = about(tilt_axis, tilt) * about(Vec3::UnitZ(), spin) *
                  Eigen::Quaterniond::FromTwoVectors(fa.normal, -Vec3::UnitZ()).toRotationMatrix();
  const Vec3 point(slide.x(), slide.y(), 0.0);
  const Vec3 xa = point - ra * fa.centroid - depth * Vec3::UnitZ();
  const Vec3 xb = -(rb * fb.centroid);
  Placed a(geometry::ConvexPolyhedron(sa), shift + scale * (turn * xa), turn * ra);
  Placed b(geometry::ConvexPolyhedron(sb), shift + scale * (turn * xb), turn * rb);
  Contact c;
  c.touching = true;
  c.normal = turn * Vec3::UnitZ();
  c.point = shift + scale * (turn * point);
  c.depth = scale * depth;
  const double size = pairLengthScale(a.body(), b.body());
  visit(a, b, c, size, shift.norm() + 4.0 * size);
}

/// The tilt of trial `trial`'s face pair, in turn: none, 1e-9, 1e-4, within the facing angle (up
/// to 19 degrees), beyond it (21 to 40 degrees: edge-face or one point), up to 5 degrees.
inline double randomTilt(int trial, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const double deg = std::numbers::pi / 180.0;
  switch (trial % 6) {
    case 0:
      return 0.0;
    case 1:
      return 1e-9 * u(rng);
    case 2:
      return 1e-4 * u(rng);
    case 3:
      return 19.0 * deg * u(rng);
    case 4:
      return (21.0 + 19.0 * (0.5 + 0.5 * u(rng))) * deg;
    default:
      return 5.0 * deg * u(rng);
  }
}

/// How trial `trial`'s pair is sunk and moved: a depth of 1e-9 to 1e-3, a scale of 1e-3 to 1e3,
/// turned at random on odd trials, moved 500 to 1,000 sizes from the origin.
struct PairMotion {
  double depth, scale;
  Mat3 turn;
  Vec3 shift;
};

inline PairMotion randomPairMotion(int trial, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  PairMotion m;
  m.depth = std::pow(10.0, -3.0 - 6.0 * (0.5 + 0.5 * u(rng)));
  m.scale = std::pow(10.0, 3.0 * u(rng));
  m.turn = trial % 2 == 0 ? Mat3::Identity() : randomRotation(rng);
  m.shift = m.scale * 1000.0 * (0.5 + 0.5 * u(rng)) * randomUnit(rng);
  return m;
}

}  // namespace polydem::contact::testing
