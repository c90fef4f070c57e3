// The declaration of check kind "kinetic_energy_ratio": its value's unit and its parameters
// (computed by module/run/checks/kinetic_energy_ratio.cpp). The kinetic energy kept through a
// particle's first contact.
#include "polydem/scene/check_kinds/kinds.h"
#include "polydem/scene/check_kinds/params.h"

namespace polydem::scene::kinds {

CheckKind kineticEnergyRatio() {
  return {"kinetic_energy_ratio",
          Quantity::kDimensionless,
          "kinetic energy after the first contact ends over that just before it began",
          {particle()}};
}

}  // namespace polydem::scene::kinds
