// The exact integrals of a piecewise-linear ground acceleration (ground_motion.h).
#include "polydem/sim/ground_motion.h"

#include <algorithm>

#include "polydem/core/error.h"
#include "polydem/core/logging.h"
#include "polydem/core/strings.h"

namespace polydem::sim {

GroundMotion::GroundMotion(std::vector<double> time, std::vector<Vec3> acceleration)
    : t_(std::move(time)), a_(std::move(acceleration)) {
  if (t_.size() < 2 || t_.size() != a_.size()) {
    throw Error(cat("GroundMotion: a record needs at least two samples, each with a time and an ",
                    "acceleration (got ", t_.size(), " times and ", a_.size(), " accelerations)"));
  }
  for (std::size_t i = 1; i < t_.size(); ++i) {
    if (!(t_[i] > t_[i - 1])) {
      throw Error(cat("GroundMotion: the record's times must increase (sample ", i, " at ", t_[i],
                      " s follows ", t_[i - 1], " s)"));
    }
  }
  v_.assign(t_.size(), Vec3::Zero());
  u_.assign(t_.size(), Vec3::Zero());
  for (std::size_t i = 0; i + 1 < t_.size(); ++i) {
    const double h = t_[i + 1] - t_[i];
    const Vec3 da = a_[i + 1] - a_[i];
    v_[i + 1] = v_[i] + a_[i] * h + da * (h / 2.0);
    u_[i + 1] = u_[i] + v_[i] * h + a_[i] * (h * h / 2.0) + da * (h * h / 6.0);
  }
}

std::size_t GroundMotion::segment(double t) const {
  // The last t_i <= t; t_n itself belongs to the last segment's end.
  const auto it = std::upper_bound(t_.begin(), t_.end(), t);
  return std::min(static_cast<std::size_t>(it - t_.begin()) - 1, t_.size() - 2);
}

Vec3 GroundMotion::acceleration(double t) const {
  if (t < t_.front() || t > t_.back()) return Vec3::Zero();
  const std::size_t i = segment(t);
  const double s = (t - t_[i]) / (t_[i + 1] - t_[i]);
  return a_[i] + (a_[i + 1] - a_[i]) * s;
}

Vec3 GroundMotion::velocity(double t) const {
  if (t <= t_.front()) return Vec3::Zero();
  if (t >= t_.back()) return v_.back();
  const std::size_t i = segment(t);
  const double h = t_[i + 1] - t_[i], tau = t - t_[i];
  return v_[i] + a_[i] * tau + (a_[i + 1] - a_[i]) * (tau * tau / (2.0 * h));
}

Vec3 GroundMotion::displacement(double t) const {
  if (t <= t_.front()) return Vec3::Zero();
  if (t >= t_.back()) return u_.back() + v_.back() * (t - t_.back());
  const std::size_t i = segment(t);
  const double h = t_[i + 1] - t_[i], tau = t - t_[i];
  return u_[i] + v_[i] * tau + a_[i] * (tau * tau / 2.0) +
         (a_[i + 1] - a_[i]) * (tau * tau * tau / (6.0 * h));
}

double GroundMotion::peakSpeed() const {
  double peak = 0.0;
  for (const Vec3& v : v_) peak = std::max(peak, v.norm());
  return peak;
}

std::optional<GroundMotion> groundMotion(const setup::Setup& scene) {
  const auto& s = scene.seismic;
  if (!s.enabled || s.record_time.empty()) return std::nullopt;
  GroundMotion ground(s.record_time, s.record_acceleration);
  const Vec3& v = ground.finalVelocity();
  if (v.norm() > 0.01 * ground.peakSpeed()) {
    log::warning(cat(scene.file, ":", s.line, ": [seismic] record ", s.record_file,
                     " ends with the ground moving at (", num(v.x()), ", ", num(v.y()), ", ",
                     num(v.z()), ") m/s, ", num(100.0 * v.norm() / ground.peakSpeed()),
                     " % of its peak velocity: no baseline correction is applied, so the fixed ",
                     "rock drifts at that velocity after ", num(ground.endTime()),
                     " s; correct the record's baseline if the ground should come to rest"));
  }
  return ground;
}

}  // namespace polydem::sim
