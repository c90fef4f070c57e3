// The motion of a simulation's free particles against where the scene put them: mean and largest
// displacement, mean and largest speed, largest angular speed, the front's advance along a
// direction. What the thesis watches on a rock slope (Keissar section 4.5: the mass is at rest
// when its mean speed is below 1e-4 m/s; fig. 4.11: its mean displacement against time) and
// what `polydem fos` decides a trial by. Every value is the same bits on any rank count (exact
// sums, max reductions).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "polydem/core/types.h"
#include "polydem/setup/setup.h"

namespace polydem::sim {
class Simulation;
}  // namespace polydem::sim

namespace polydem::run {

struct FreeMotion {
  std::int64_t particles = 0;      // free particles measured
  double mean_displacement = 0.0;  // m, of the centroids from their start
  double max_displacement = 0.0;
  double mean_speed = 0.0;  // m/s, of the centroids (leapfrog half step)
  double max_speed = 0.0;
  double max_angular_speed = 0.0;  // rad/s
  double front_advance = 0.0;  // m: max of x . d now minus max of x . d at the start (direction d)
};

class FreeMotionMeter {
 public:
  /// Measures the free particles of `sim` whose labels start with `label_prefix` (all free ones
  /// when empty), against their start in the scene; `direction` (unit) for front_advance.
  FreeMotionMeter(const sim::Simulation& sim, const std::string& label_prefix = "",
                  const std::optional<Vec3>& direction = std::nullopt);
  /// Collective over the simulation's communicator.
  FreeMotion measure(const sim::Simulation& sim) const;
  /// Free particles selected (the same on every rank).
  std::int64_t selected() const { return selected_; }

 private:
  bool isChosen(Uid uid) const { return uid < start_.size() && chosen_[uid]; }
  std::vector<Vec3> start_;   // by uid: the centroid the scene starts it at
  std::vector<char> chosen_;  // by uid
  std::int64_t selected_ = 0;
  std::optional<Vec3> direction_;
  double front0_ = 0.0;
};

/// Whether `label` is `prefix` followed by "_" and more ("slope_12" for prefix "slope"), or
/// `prefix` itself; an empty prefix matches every label.
bool matchesPrefix(const std::string& label, const std::string& prefix);

}  // namespace polydem::run
