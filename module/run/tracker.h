// Tracker: the state of a few labelled particles, gathered every step onto every rank, for checks
// and the series file. One small MPI_Allreduce per step: the owner writes its particles' values,
// every other rank zeros, so the sum is exact.
#pragma once

#include <string>
#include <vector>

#include "polydem/core/types.h"

namespace polydem::sim {
class Simulation;
}  // namespace polydem::sim

namespace polydem::run {

struct TrackedState {
  Vec3 position = Vec3::Zero();
  Quat orientation = Quat::Identity();
  Vec3 velocity = Vec3::Zero();  // centroid, at the leapfrog half step t - dt/2
  Vec3 angular_velocity = Vec3::Zero();
  double kinetic_energy = 0.0;
  int contacts = 0;  // touching contacts of the particle this step
};

class Tracker {
 public:
  /// Tracks the particles with these uids (the lists of checks and monitors, merged).
  void track(Uid uid);
  bool empty() const { return uids_.empty(); }
  /// Index of a tracked uid in states().
  int slot(Uid uid) const;

  /// Gathers the current states (collective). Call after each step.
  void gather(const sim::Simulation& sim);
  const std::vector<TrackedState>& states() const { return states_; }
  const std::vector<TrackedState>& initial() const { return initial_; }
  /// The initial states (of the main stage) as numbers, and back (a checkpoint's run state).
  std::vector<double> initialState() const;
  void restoreInitial(const std::vector<double>& values);

 private:
  std::vector<Uid> uids_;
  std::vector<TrackedState> states_, initial_;
  std::vector<double> buffer_, sum_;
  bool have_initial_ = false;
};

/// Rotation angle (rad) between two orientations, in [0, pi].
double rotationAngle(const Quat& from, const Quat& to);
/// Rotation angle about `axis` (unit): the twist part of the relative rotation.
double twistAngle(const Quat& from, const Quat& to, const Vec3& axis);

}  // namespace polydem::run
