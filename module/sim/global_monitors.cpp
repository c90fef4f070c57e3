// The global monitors of a state (global_monitors.h).
#include "polydem/sim/global_monitors.h"

#include <algorithm>

#include "polydem/core/exact_sum.h"
#include "polydem/core/mpi_env.h"

namespace polydem::sim {

GlobalMonitors globalMonitors(const StepState& s) {
  ExactSum kinetic, speed;
  dynamics::ForceRatio ratio = s.ratio_local;
  std::int64_t contacts = 0, free_particles = 0;
  double max_speed = 0.0;
  for (std::size_t i = 0; i < s.storage.localCount(); ++i) {
    const auto& p = s.storage[i];
    if (!p.isFree()) continue;
    ++free_particles;
    kinetic += dynamics::kineticEnergy(p, s.massProperties(i));
    const double v = p.velocity.norm();
    speed += v;
    max_speed = std::max(max_speed, v);
  }
  for (const auto& w : s.contact_phase.work())
    contacts += w.has(PairWork::kTouching) && w.has(PairWork::kALocal);
  kinetic.allreduce(s.comm);
  speed.allreduce(s.comm);
  ratio.allreduce(s.comm);
  GlobalMonitors m;
  m.kinetic_energy = kinetic.value();
  m.force_ratio = ratio.value();
  m.contacts = mpi::allreduceSum(contacts, s.comm);
  m.particles = mpi::allreduceSum(free_particles, s.comm);
  m.max_speed = mpi::allreduceMax(max_speed, s.comm);
  m.mean_speed = m.particles > 0 ? speed.value() / static_cast<double>(m.particles) : 0.0;
  return m;
}

double globalForceRatio(const StepState& s) {
  dynamics::ForceRatio ratio = s.ratio_local;
  ratio.allreduce(s.comm);
  return ratio.value();
}

}  // namespace polydem::sim
