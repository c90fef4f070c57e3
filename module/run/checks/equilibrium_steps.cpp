// Check kind "equilibrium_steps": the steps the initial-equilibrium stage took to bring the force
// ratio R below its target (Keissar table 3.7).
#include <limits>

#include "polydem/core/strings.h"
#include "polydem/run/checks/final_check.h"
#include "polydem/run/checks/kinds.h"
#include "polydem/sim/simulation.h"

namespace polydem::run::kinds {

namespace {

double steps(sim::Simulation& sim, std::string& note) {
  if (!sim.scene().equilibrium.enabled) {
    note = "the scene has no [equilibrium] stage";
    return std::numeric_limits<double>::quiet_NaN();
  }
  if (!sim.equilibriumReached()) {
    note = cat("R < ", sim.scene().equilibrium.force_ratio, " not reached within ",
               sim.equilibriumSteps(), " steps");
    return std::numeric_limits<double>::quiet_NaN();
  }
  return static_cast<double>(sim.equilibriumSteps());
}

}  // namespace

std::unique_ptr<Check> equilibriumSteps(const setup::Setup&, const setup::CheckSpec& spec,
                                        Tracker&) {
  return std::make_unique<FinalCheck>(spec, steps);
}

}  // namespace polydem::run::kinds
