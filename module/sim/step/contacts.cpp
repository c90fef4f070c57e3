// Contact phase: the forces of every candidate pair (sim/contact_phase.h).
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

ContactSetup Simulation::contactSetup() const {
  ContactSetup setup;
  setup.shapes = &shapes_;
  setup.kernel = kernel_.get();
  setup.law = stage_ == Stage::kEquilibrium ? &law_equilibrium_ : &law_main_;
  setup.materials = static_cast<int>(materials_.size());
  setup.plane_joint = &plane_joint_;
  setup.joint_law = stage_ == Stage::kEquilibrium ? &joint_law_equilibrium_ : &joint_law_main_;
  setup.drivers = &scene_.drivers;
  setup.model = contact_model_;
  setup.overlap_centroid = overlap_centroid_;
  setup.margin = margin_;
  setup.dt = dt();
  setup.time = stage_ == Stage::kEquilibrium ? 0.0 : time();
  return setup;
}

void Simulation::computeContacts() {
  contact_stats_ = contact_phase_.run(contactSetup(), storage_, candidates_, history_, forces_);
  // The work of this phase, and where it was if the decomposition is weighed after this step
  // (the records hold storage indices, valid only until the particles move).
  const auto every = scene_.domain.rebalance_every;
  if (sample_load_ || (every > 0 && (loop_.step() + 1) % every == 0)) {
    load_sample_ = sampleLoad(storage_, contact_phase_.records(), load_model_);
    last_work_ = load_sample_.work;
    sample_load_ = false;
  } else {
    last_work_ = stepWork(storage_, contact_phase_.records(), load_model_);
  }
  // Gravity, and the pseudo-static earthquake load when the scene has one (sim/seismic.h).
  const Vec3 body = bodyAcceleration(scene_);
  for (std::size_t i = 0; i < storage_.localCount(); ++i) {
    if (storage_[i].isFree()) forces_[i].addBodyForce(storage_.mass(i) * body);
  }
  if (scene_.water.enabled) {
    addWaterForces(scene_.water, stage_ == Stage::kEquilibrium ? 0.0 : time(), shapes_, storage_,
                   std::span<dynamics::ForceAccumulator>(forces_.data(), storage_.localCount()));
  }
  if (!bolts_.empty()) {
    bolts_.addForces(storage_,
                     std::span<dynamics::ForceAccumulator>(forces_.data(), storage_.localCount()),
                     stage_ == Stage::kEquilibrium ? 0.0 : time(), comm_);
  }
  applyForceOperators();
  ratio_local_.clear();
  for (std::size_t i = 0; i < storage_.localCount(); ++i) {
    if (storage_[i].isFree()) ratio_local_.add(forces_[i]);
  }
}

}  // namespace polydem::sim
