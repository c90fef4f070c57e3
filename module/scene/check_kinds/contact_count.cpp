// The declaration of check kind "contact_count": its value's unit and its parameters (computed by
// module/run/checks/contact_count.cpp). The touching pairs at the end.
#include "polydem/scene/check_kinds/kinds.h"
#include "polydem/scene/check_kinds/params.h"

namespace polydem::scene::kinds {

CheckKind contactCount() {
  return {"contact_count",
          Quantity::kDimensionless,
          "touching pairs at the end, each counted once",
          {}};
}

}  // namespace polydem::scene::kinds
