// The declaration of check kind "max_contact_force": its value's unit and its parameters (computed
// by module/run/checks/max_contact_force.cpp). The largest contact force across an axis over the
// mean weight.
#include "polydem/scene/check_kinds/kinds.h"
#include "polydem/scene/check_kinds/params.h"

namespace polydem::scene::kinds {

CheckKind maxContactForce() {
  return {
      "max_contact_force",
      Quantity::kDimensionless,
      "largest contact force between free particles across `axis`, over their mean weight",
      {direction("axis", false, "the force component along it is left out (default: gravity)")}};
}

}  // namespace polydem::scene::kinds
