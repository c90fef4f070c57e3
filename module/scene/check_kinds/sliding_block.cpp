// The declaration of check kind "sliding_block": its value's unit and its parameters (computed by
// module/run/checks/sliding_block.cpp). A block launched along an incline against Zhao eqs. 41-42.
#include "polydem/scene/check_kinds/kinds.h"
#include "polydem/scene/check_kinds/params.h"

namespace polydem::scene::kinds {

CheckKind slidingBlock() {
  return {"sliding_block",
          Quantity::kDimensionless,
          "largest |numerical - analytical| over the largest analytical value (Zhao eqs. 41-42)",
          {particle(), theta(true),
           number("mu", true, Quantity::kDimensionless, 0.0, kInf, false, false,
                  "friction coefficient"),
           number("u0", true, Quantity::kVelocity, 0.0, kInf, false, false,
                  "launch speed up the slope, m/s"),
           gravity(), direction("direction", true, "up the slope"),
           word("quantity", {"displacement", "velocity"},
                "compare the \"displacement\" (default) or the \"velocity\"")}};
}

}  // namespace polydem::scene::kinds
