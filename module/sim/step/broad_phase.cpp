// Broad phase: candidate pairs over owned and ghost particles (a superset).
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

// The broad phase's input from the storage; returns the largest radius.
double Simulation::fillSphereSet() {
  const std::size_t n = storage_.size();
  centers_.resize(n);
  radii_.resize(n);
  uids_.resize(n);
  active_.resize(n);
  double r_max = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    const auto& p = storage_[i];
    centers_[i] = storage_.placedPosition(i);
    radii_[i] = shapes_[p.shape].circumradius;
    uids_[i] = p.uid;
    active_[i] = i < storage_.localCount() && p.isFree();
    r_max = std::max(r_max, radii_[i]);
  }
  return r_max;
}

void Simulation::findCandidates() {
  findPairs(candidates_);
  // Before the contact phase allocates its records and histories for every pair.
  if (candidates_.size() * bytesPerCandidatePair() > (std::size_t{64} << 20)) {
    if (const auto problem = pairMemoryProblem(scene_, storage_, radii_, margin_, candidates_,
                                               loop_.step(), availableMemoryBytes())) {
      throw SimulationError(*problem);
    }
  }
}

void Simulation::findPairs(std::vector<broadphase::CandidatePair>& out) {
  const double r_max = fillSphereSet();
  // A superset of the contact phase's own test, which is made in each pair's canonical frame.
  const double margin = margin_ + 1e-9 * 2.0 * r_max;
  try {
    broadphase_->findPairs({centers_, radii_, uids_, active_}, margin, out);
  } catch (const std::bad_alloc&) {
    throw SimulationError(cat("step ", loop_.step(), ": the broad phase ran out of memory for ",
                              "its candidate pairs (", out.size(),
                              " so far): particles overlap massively, or the contact margin of ",
                              margin_, " m reaches across many of them; check the scene for ",
                              "particles placed on top of each other and its contact_margin"));
  }
}

}  // namespace polydem::sim
