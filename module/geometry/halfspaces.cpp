#include "polydem/geometry/halfspaces.h"

#include <algorithm>
#include <limits>

namespace polydem::geometry {

double Halfspaces::minSlack(const Vec3& x, int begin, int end) const {
  if (end < 0) end = size();
  double smallest = std::numeric_limits<double>::infinity();
  for (int i = begin; i < end; ++i) smallest = std::min(smallest, slack(i, x));
  return smallest;
}

// Plane i holds the points with t * (a_i . u) <= s_i, s_i = d_i - a_i . x: an upper end for
// a_i . u > 0, a lower end for a_i . u < 0, and all t or none for a plane parallel to the line.
Halfspaces::Chord Halfspaces::chord(const Vec3& x, const Vec3& u) const {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  Chord c{-kInf, kInf};
  for (int i = 0; i < size(); ++i) {
    const double s = slack(i, x);
    const double rate = ax_[i] * u.x() + ay_[i] * u.y() + az_[i] * u.z();
    if (rate > 0.0) {
      c.t_max = std::min(c.t_max, s / rate);
    } else if (rate < 0.0) {
      c.t_min = std::max(c.t_min, s / rate);
    } else if (s < 0.0) {
      return Chord{kInf, -kInf};
    }
  }
  return c;
}

}  // namespace polydem::geometry
