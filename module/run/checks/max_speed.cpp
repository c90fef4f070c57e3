// Check kind "max_speed": the largest speed of the free particles at the end of the run.
#include "polydem/run/checks/final_check.h"
#include "polydem/run/checks/kinds.h"
#include "polydem/sim/simulation.h"

namespace polydem::run::kinds {

std::unique_ptr<Check> maxSpeed(const setup::Setup&, const setup::CheckSpec& spec, Tracker&) {
  return std::make_unique<FinalCheck>(
      spec, [](sim::Simulation& sim, std::string&) { return sim.monitors().max_speed; });
}

}  // namespace polydem::run::kinds
