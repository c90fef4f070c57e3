// Simulation: the mass properties, global monitors and state hash of its current state.
#include "polydem/sim/simulation.h"

#include <chrono>
#include <cmath>

#include "polydem/core/error.h"
#include "polydem/core/exact_sum.h"
#include "polydem/core/logging.h"
#include "polydem/core/memory.h"
#include "polydem/core/mpi_env.h"
#include "polydem/core/state_hash.h"
#include "polydem/core/strings.h"
#include "polydem/domain/partition.h"
#include "polydem/domain/rebalance.h"
#include "polydem/dynamics/driver.h"
#include "polydem/dynamics/integrator.h"
#include "polydem/sim/pair_memory.h"
#include "polydem/sim/seismic.h"
#include "polydem/sim/water.h"

namespace polydem::sim {

dynamics::MassProperties Simulation::massProperties(std::size_t i) const {
  const auto& p = storage_[i];
  const double density = densities_[p.material];
  const auto& s = shapes_[p.shape];
  return {density * s.volume, density * s.principal_moments};
}

GlobalMonitors Simulation::monitors() {
  ExactSum kinetic, speed;
  dynamics::ForceRatio ratio = ratio_local_;
  std::int64_t contacts = 0, free_particles = 0;
  double max_speed = 0.0;
  for (std::size_t i = 0; i < storage_.localCount(); ++i) {
    const auto& p = storage_[i];
    if (!p.isFree()) continue;
    ++free_particles;
    kinetic += dynamics::kineticEnergy(p, massProperties(i));
    const double v = p.velocity.norm();
    speed += v;
    max_speed = std::max(max_speed, v);
  }
  for (const auto& r : contact_phase_.records()) contacts += r.touching && r.a_is_local;
  kinetic.allreduce(comm_);
  speed.allreduce(comm_);
  ratio.allreduce(comm_);
  GlobalMonitors m;
  m.kinetic_energy = kinetic.value();
  m.force_ratio = ratio.value();
  m.contacts = mpi::allreduceSum(contacts, comm_);
  m.particles = mpi::allreduceSum(free_particles, comm_);
  m.max_speed = mpi::allreduceMax(max_speed, comm_);
  m.mean_speed = m.particles > 0 ? speed.value() / static_cast<double>(m.particles) : 0.0;
  return m;
}

comm::StateHash Simulation::stateHash() const {
  comm::StateHash h = comm::globalStateHash(storage_, history_, comm_);
  // The bolts' state, replicated on every rank, joins the combined hash; a scene without bolts
  // keeps its hash.
  if (!bolts_.empty()) {
    BitHasher bolts;
    bolts.add(h.combined);
    for (const auto& b : bolts_.states()) {
      bolts.add(b.axial_plastic);
      bolts.add(b.shear_plastic);
      bolts.add(std::uint64_t{b.broken});
    }
    h.combined = bolts.value();
  }
  return h;
}

}  // namespace polydem::sim
