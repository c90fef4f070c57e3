// Basic numeric types shared by every module.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>

namespace polydem {

using Vec3 = Eigen::Vector3d;
using Vec2 = Eigen::Vector2d;
using Mat3 = Eigen::Matrix3d;
using Quat = Eigen::Quaterniond;

/// Global, never reused particle id. Canonical pair order and per-particle force sums are taken
/// in uid order, which is what makes a run bit-for-bit identical on any rank count.
using Uid = std::uint64_t;

inline constexpr double kPi = 3.14159265358979323846;

inline double degToRad(double deg) {
  return deg * kPi / 180.0;
}
inline double radToDeg(double rad) {
  return rad * 180.0 / kPi;
}

}  // namespace polydem
