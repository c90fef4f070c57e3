// The declaration of check kind "equilibrium_steps": its value's unit and its parameters (computed
// by module/run/checks/equilibrium_steps.cpp). The steps of the initial-equilibrium stage.
#include "polydem/scene/check_kinds/kinds.h"
#include "polydem/scene/check_kinds/params.h"

namespace polydem::scene::kinds {

CheckKind equilibriumSteps() {
  return {
      "equilibrium_steps", Quantity::kDimensionless, "steps of the initial-equilibrium stage", {}};
}

}  // namespace polydem::scene::kinds
