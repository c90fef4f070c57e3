// The scene's [[operator]]s as force operators of the step (docs/scene-format.md "Operators"):
// one that names a library is loaded from it (sim/operator_library.h), one that names none is
// supplied by the program that runs the scene (the Python module's Simulation(scene,
// operators={...})). They run at the step's "force operators" place in file order, each timed
// under its name, before any operator added in code (Simulation::addForceOperator).
#pragma once

#include <map>
#include <string>
#include <vector>

#include "polydem/setup/setup.h"
#include "polydem/sim/force_operator.h"
#include "polydem/sim/step/step_state.h"

namespace polydem::sim {

/// Operators a program supplies by name for the scene's [[operator]]s without a library.
using HostOperators = std::map<std::string, ForceOperator>;

/// The scene's operators, in file order. Throws InputError at the [[operator]]'s line for a
/// library that does not load, a name the library does not define, a name of an operator of the
/// step, or an operator without a library that `host` does not supply; polydem::Error for an
/// operator of `host` that the scene does not name.
std::vector<NamedForceOperator> sceneOperators(const setup::Setup& scene,
                                               const HostOperators& host);

}  // namespace polydem::sim
