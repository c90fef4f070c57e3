// The ground motion of an acceleration record ([seismic] record, docs/scene-format.md
// "Earthquakes"): the ground's acceleration a(t) is linear between the record's samples and zero
// before the first and after the last one; its velocity and displacement are the exact integrals
// of that piecewise-linear a(t), starting from rest at the first sample:
//
//   on [t_i, t_i+1], tau = t - t_i, h = t_i+1 - t_i, da = a_i+1 - a_i:
//   v(t) = v_i + a_i tau + da tau^2 / (2 h)                      (the trapezoid rule at t_i+1)
//   u(t) = u_i + v_i tau + a_i tau^2 / 2 + da tau^3 / (6 h)      (the exact cubic)
//
// and after the last sample v = v_n, u = u_n + v_n (t - t_n). No baseline correction is applied:
// a record that ends with a velocity makes the ground drift at it (groundMotion() warns).
//
// Every fixed particle moves with the ground, translation only (Simulation::integrate): each step
// from t to t + dt it is displaced by u(t + dt) - u(t) and carries the velocity v(t + dt/2), the
// half-step velocity the free particles' leapfrog and the contact law use. Both are pure functions
// of the simulation time, computed alike on every rank, and the positions and velocities they
// give are the particles' own state, so a checkpoint needs nothing more and a restart on any rank
// count continues with the same bits.
#pragma once

#include <optional>
#include <vector>

#include "polydem/core/types.h"
#include "polydem/setup/setup.h"

namespace polydem::sim {

class GroundMotion {
 public:
  /// `time` strictly increasing (s), one acceleration (m/s^2) per time, at least two samples.
  GroundMotion(std::vector<double> time, std::vector<Vec3> acceleration);

  Vec3 acceleration(double t) const;
  Vec3 velocity(double t) const;
  Vec3 displacement(double t) const;

  /// The velocity the ground keeps after the last sample.
  const Vec3& finalVelocity() const { return v_.back(); }
  /// The largest |v| at the samples.
  double peakSpeed() const;
  double endTime() const { return t_.back(); }

 private:
  /// Index i of the segment [t_i, t_i+1] holding t (t_0 <= t < t_n).
  std::size_t segment(double t) const;

  std::vector<double> t_;
  std::vector<Vec3> a_, v_, u_;  // at the samples
};

/// The ground motion of the scene's [seismic] record, none without one. Warns (rank 0) when the
/// record ends with a ground velocity above 1 % of its peak: the fixed rock then drifts.
std::optional<GroundMotion> groundMotion(const setup::Setup& scene);

}  // namespace polydem::sim
