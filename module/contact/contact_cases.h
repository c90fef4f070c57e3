// The seven contact types of BENCHMARKS.md section C (Keissar section 3.3, tables 3.1-3.6), with
// their analytical answer, and the criteria by which a kernel's result is judged correct.
//
// B is fixed below, A above; contact features meet at the origin, B's top feature at z = 0 and A's
// lowest feature at z = -1e-5, so every case has normal (0,0,1), point (0,0,-5e-6), depth 1e-5.
#pragma once

#include <string>
#include <vector>

#include "polydem/contact/contact.h"

namespace polydem::contact {

struct ContactCase {
  std::string id;  // C-VV, C-VE, C-VF, C-EEp, C-EEx, C-EF, C-FF
  std::string description;
  std::vector<Vec3> a, b;  // world vertices of A (above) and B (below)
  Vec3 normal;             // analytical answer
  Vec3 point;
  double depth = 0.0;
  double size = 1.0;  // particle size the point tolerance is relative to
};

/// The seven cases at unit size.
std::vector<ContactCase> contactTypeCases();

/// The same case after x -> scale * (R x) + t, with the answer moved along.
ContactCase transformed(const ContactCase& c, const Mat3& rotation, const Vec3& translation,
                        double scale);

/// Correctness criteria of BENCHMARKS.md section C.
struct Criteria {
  static constexpr double kNormalRad = 1e-6;  // normal within 1e-6 rad
  static constexpr double kPointRel = 1e-6;   // point within 1e-6 of the particle size
  static constexpr double kDepthRel = 1e-3;   // depth within 1e-3 relative
};

struct CaseEvaluation {
  bool touching = false;
  double normal_error_rad = 0.0;
  double point_error = 0.0;  // relative to the case's size
  double depth_error = 0.0;  // relative to the analytical depth; 0 for potential kernels
  bool normal_ok = false, point_ok = false, depth_ok = false;
  bool correct() const { return touching && normal_ok && point_ok && depth_ok; }
};

/// Judges `result` against the case's answer. For potential kernels (ForceModel::kPotential) the
/// depth is not a penetration and is not judged; the force direction and point of action are.
CaseEvaluation evaluate(const ContactCase& c, const Contact& result);

/// Angle between two unit vectors, accurate for tiny angles.
double angleBetween(const Vec3& u, const Vec3& v);

}  // namespace polydem::contact
