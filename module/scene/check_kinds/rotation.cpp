// The declaration of check kind "rotation": its value's unit and its parameters (computed by
// module/run/checks/rotation.cpp). The largest rotation angle of particles.
#include "polydem/scene/check_kinds/kinds.h"
#include "polydem/scene/check_kinds/params.h"

namespace polydem::scene::kinds {

CheckKind rotation() {
  return {"rotation",
          Quantity::kPhase,
          "largest rotation angle of the particles, rad",
          {particles(), direction("axis", false, "only the rotation about it (default: any)")}};
}

}  // namespace polydem::scene::kinds
