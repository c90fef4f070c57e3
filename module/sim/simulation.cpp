// Simulation: the mass properties, global monitors and state hash of its current state.
#include "polydem/sim/simulation.h"

#include <algorithm>

#include "polydem/core/exact_sum.h"
#include "polydem/core/mpi_env.h"
#include "polydem/core/state_hash.h"

namespace polydem::sim {

GlobalMonitors Simulation::monitors() {
  ExactSum kinetic, speed;
  dynamics::ForceRatio ratio = state_.ratio_local;
  std::int64_t contacts = 0, free_particles = 0;
  double max_speed = 0.0;
  for (std::size_t i = 0; i < state_.storage.localCount(); ++i) {
    const auto& p = state_.storage[i];
    if (!p.isFree()) continue;
    ++free_particles;
    kinetic += dynamics::kineticEnergy(p, massProperties(i));
    const double v = p.velocity.norm();
    speed += v;
    max_speed = std::max(max_speed, v);
  }
  for (const auto& r : state_.contact_phase.records()) contacts += r.touching && r.a_is_local;
  kinetic.allreduce(state_.comm);
  speed.allreduce(state_.comm);
  ratio.allreduce(state_.comm);
  GlobalMonitors m;
  m.kinetic_energy = kinetic.value();
  m.force_ratio = ratio.value();
  m.contacts = mpi::allreduceSum(contacts, state_.comm);
  m.particles = mpi::allreduceSum(free_particles, state_.comm);
  m.max_speed = mpi::allreduceMax(max_speed, state_.comm);
  m.mean_speed = m.particles > 0 ? speed.value() / static_cast<double>(m.particles) : 0.0;
  return m;
}

comm::StateHash Simulation::stateHash() const {
  comm::StateHash h = comm::globalStateHash(state_.storage, state_.history, state_.comm);
  // The bolts' state, replicated on every rank, joins the combined hash; a scene without bolts
  // keeps its hash.
  if (!state_.bolts.empty()) {
    BitHasher bolts;
    bolts.add(h.combined);
    for (const auto& b : state_.bolts.states()) {
      bolts.add(b.axial_plastic);
      bolts.add(b.shear_plastic);
      bolts.add(std::uint64_t{b.broken});
    }
    h.combined = bolts.value();
  }
  return h;
}

}  // namespace polydem::sim
