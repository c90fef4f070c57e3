// Scale-free tolerances. Every geometric comparison in polydem is made relative to a length
// scale taken from the objects involved (usually the sum of the two circumradii of a pair), so
// that a scene in millimetres behaves exactly like the same scene in metres.
#pragma once

#include <cmath>

namespace polydem {

/// Relative tolerances, as fractions of the length scale they are applied to.
struct RelTol {
  /// Two points closer than this (relative) are the same point; used for duplicate vertices.
  static constexpr double kPoint = 1e-10;
  /// A point this close (relative) to a plane lies on it; used for coplanarity and face merging.
  static constexpr double kPlane = 1e-10;
  /// Convergence of iterative distance / penetration algorithms (GJK, EPA, FCP).
  static constexpr double kIteration = 1e-12;
};

/// Absolute tolerance for a quantity of length scale `scale`.
inline double absTol(double scale, double rel) {
  return std::abs(scale) * rel;
}

}  // namespace polydem
