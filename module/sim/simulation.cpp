// Simulation: stepping and running its stages (stages.h), the state hash of its current state.
#include "polydem/sim/simulation.h"

#include <algorithm>

#include "polydem/core/error.h"
#include "polydem/core/mpi_env.h"
#include "polydem/core/state_hash.h"
#include "polydem/core/strings.h"

namespace polydem::sim {

void requireStopCondition(const setup::Setup& scene) {
  // The scene reader requires one; a scene changed from Python may have neither, and the loop's
  // own stop condition (the step hook) would then never hold.
  if (!scene.end_time && !scene.steps) {
    throw Error(cat("scene ", scene.file, ": neither end_time nor steps is set: nothing would ",
                    "stop the run"));
  }
}

void Simulation::step() {
  requireBetweenSteps("step");
  state_.loop.singleStep();
}

std::int64_t Simulation::runEquilibrium() {
  requireBetweenSteps("runEquilibrium");
  return stages_.runEquilibrium();
}

timeloop::StopReason Simulation::run() {
  requireBetweenSteps("run");
  requireStopCondition(state_.scene);
  return stages_.run();
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
