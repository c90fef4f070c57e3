// A library of user force operators that a scene names (docs/scene-format.md "Operators"):
//
//   #include "polydem/sim/operator_library.h"
//   POLYDEM_FORCE_OPERATOR(anchor_pull) {
//     for (std::size_t i = 0; i < step.forces.size(); ++i) step.forces[i].addBodyForce(...);
//   }
//
// built as a shared library (CMake: add_library(myops MODULE ops.cpp)) and named in the scene:
//
//   [[operator]]
//   name = "anchor_pull"
//   library = "libmyops.so"
//
// Each operator is a C function the library exports under the name "polydem_operator_" + its
// name: the simulation finds it by that name with dlsym (sim/scene_operators.cpp), so a library
// needs no registry and no initialisation, and may hold any number of operators. The body is a
// force operator's (sim/force_operator.h): `step` is the ForceStep of this rank's particles.
#pragma once

#include "polydem/sim/force_operator.h"

namespace polydem::sim {

/// The symbol under which a library exports the operator `name` is this prefix + name.
inline constexpr const char* kOperatorSymbolPrefix = "polydem_operator_";
/// The type of that symbol.
using LibraryOperator = void (*)(const ForceStep& step);

}  // namespace polydem::sim

/// Defines the force operator NAME (a C identifier, the name the scene gives) as an exported
/// function of this library; the braces that follow are its body, with `step` in scope.
#define POLYDEM_FORCE_OPERATOR(NAME)                                              \
  extern "C" __attribute__((visibility("default"))) void polydem_operator_##NAME( \
      const ::polydem::sim::ForceStep& step)
