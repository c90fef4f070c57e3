// The declaration of check kind "pair_separation": its value's unit and its parameters (computed by
// module/run/checks/pair_separation.cpp). When two particles that pressed on each other stop (a
// rock-slope kind).
#include "polydem/scene/check_kinds/kinds.h"
#include "polydem/scene/check_kinds/params.h"

namespace polydem::scene::kinds {

CheckKind pairSeparation() {
  return {"pair_separation",
          Quantity::kTime,
          "first time two particles that pressed on each other with at least `min_force` stop, s",
          {particles("the two labels, \"a, b\""),
           number("min_force", false, Quantity::kForce, 0.0, kInf, false, false,
                  "the force that counts as pressing, N (default 0)")}};
}

}  // namespace polydem::scene::kinds
