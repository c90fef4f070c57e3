// The declaration of check kind "mean_speed": its value's unit and its parameters (computed by
// module/run/checks/mean_speed.cpp). The mean speed of the free particles at the end.
#include "polydem/scene/check_kinds/kinds.h"
#include "polydem/scene/check_kinds/params.h"

namespace polydem::scene::kinds {

CheckKind meanSpeed() {
  return {
      "mean_speed", Quantity::kVelocity, "mean speed of the free particles at the end, m/s", {}};
}

}  // namespace polydem::scene::kinds
