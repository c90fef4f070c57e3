// Check kind "contact_count": the touching pairs at the end of the run, each counted once (cubes
// pushing their neighbours make new contacts).
#include "polydem/run/checks/final_check.h"
#include "polydem/run/checks/kinds.h"
#include "polydem/sim/simulation.h"

namespace polydem::run::kinds {

std::unique_ptr<Check> contactCount(const setup::Setup&, const setup::CheckSpec& spec, Tracker&) {
  return std::make_unique<FinalCheck>(spec, [](sim::Simulation& sim, std::string&) {
    return static_cast<double>(sim.monitors().contacts);
  });
}

}  // namespace polydem::run::kinds
