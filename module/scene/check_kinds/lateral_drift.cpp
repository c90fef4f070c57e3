// The declaration of check kind "lateral_drift": its value's unit and its parameters (computed by
// module/run/checks/lateral_drift.cpp). A particle's drift across its travel, relative to the
// travel.
#include "polydem/scene/check_kinds/kinds.h"
#include "polydem/scene/check_kinds/params.h"

namespace polydem::scene::kinds {

CheckKind lateralDrift() {
  return {"lateral_drift",
          Quantity::kDimensionless,
          "largest drift across `lateral` divided by the final travel along `direction` (a ratio)",
          {particle(), direction("direction", true, "of travel"),
           direction("lateral", true, "across the travel")}};
}

}  // namespace polydem::scene::kinds
