#include "polydem/run/free_motion.h"

#include <algorithm>
#include <cmath>

#include "polydem/core/exact_sum.h"
#include "polydem/core/mpi_env.h"
#include "polydem/particles/particle_storage.h"
#include "polydem/sim/simulation.h"

namespace polydem::run {

bool matchesPrefix(const std::string& label, const std::string& prefix) {
  if (prefix.empty()) return true;
  if (label.compare(0, prefix.size(), prefix) != 0) return false;
  return label.size() == prefix.size() || label[prefix.size()] == '_';
}

FreeMotionMeter::FreeMotionMeter(const sim::Simulation& sim, const std::string& label_prefix,
                                 const std::optional<Vec3>& direction)
    : direction_(direction) {
  Uid top = 0;
  for (const auto& p : sim.scene().particles) top = std::max(top, p.uid);
  start_.assign(top + 1, Vec3::Zero());
  chosen_.assign(top + 1, 0);
  front0_ = -INFINITY;
  for (const auto& p : sim.scene().particles) {
    if (p.fixed || p.driver >= 0 || !matchesPrefix(p.label, label_prefix)) continue;
    start_[p.uid] = sim.initialCentroid(p);
    chosen_[p.uid] = 1;
    ++selected_;
    if (direction_) front0_ = std::max(front0_, start_[p.uid].dot(*direction_));
  }
}

FreeMotion FreeMotionMeter::measure(const sim::Simulation& sim) const {
  ExactSum displacement, speed;
  double local_max[4] = {0.0, 0.0, 0.0, -INFINITY};  // displacement, speed, angular, front
  std::int64_t count = 0;
  const auto& storage = sim.particles();
  for (std::size_t i = 0; i < storage.localCount(); ++i) {
    const auto& p = storage[i];
    if (!p.isFree() || !isChosen(p.uid)) continue;
    ++count;
    const double d = (p.position - start_[p.uid]).norm();
    const double v = p.velocity.norm();
    const Vec3 w =
        particles::angularVelocityOf(p.orientation.toRotationMatrix(),
                                     sim.massProperties(i).principal_inertia, p.angular_momentum);
    displacement += d;
    speed += v;
    local_max[0] = std::max(local_max[0], d);
    local_max[1] = std::max(local_max[1], v);
    local_max[2] = std::max(local_max[2], w.norm());
    if (direction_) local_max[3] = std::max(local_max[3], p.position.dot(*direction_));
  }
  displacement.allreduce(sim.comm());
  speed.allreduce(sim.comm());
  double global_max[4];
  MPI_Allreduce(local_max, global_max, 4, MPI_DOUBLE, MPI_MAX, sim.comm());
  FreeMotion m;
  m.particles = mpi::allreduceSum(count, sim.comm());
  const double n = m.particles > 0 ? static_cast<double>(m.particles) : 1.0;
  m.mean_displacement = displacement.value() / n;
  m.mean_speed = speed.value() / n;
  m.max_displacement = global_max[0];
  m.max_speed = global_max[1];
  m.max_angular_speed = global_max[2];
  m.front_advance = direction_ && m.particles > 0 ? global_max[3] - front0_ : 0.0;
  return m;
}

}  // namespace polydem::run
