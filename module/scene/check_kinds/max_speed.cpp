// The declaration of check kind "max_speed": its value's unit and its parameters (computed by
// module/run/checks/max_speed.cpp). The largest speed of the free particles at the end.
#include "polydem/scene/check_kinds/kinds.h"
#include "polydem/scene/check_kinds/params.h"

namespace polydem::scene::kinds {

CheckKind maxSpeed() {
  return {
      "max_speed", Quantity::kVelocity, "largest speed of the free particles at the end, m/s", {}};
}

}  // namespace polydem::scene::kinds
