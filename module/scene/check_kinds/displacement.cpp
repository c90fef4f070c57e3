// The declaration of check kind "displacement": its value's unit and its parameters (computed by
// module/run/checks/displacement.cpp). The largest (or final) displacement of particles.
#include "polydem/scene/check_kinds/kinds.h"
#include "polydem/scene/check_kinds/params.h"

namespace polydem::scene::kinds {

CheckKind displacement() {
  return {"displacement",
          Quantity::kLength,
          "largest (or final) displacement of the particles, m",
          {particles(), direction("direction", false, "only the component along it (default: all)"),
           word("at", {"max", "end"}, "\"max\" over the run (default) or at the \"end\"")}};
}

}  // namespace polydem::scene::kinds
