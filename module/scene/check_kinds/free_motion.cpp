// The declaration of check kind "free_motion": its value's unit and its parameters (computed by
// module/run/checks/free_motion.cpp). A statistic of the free blocks' motion (a rock-slope kind).
#include "polydem/scene/check_kinds/kinds.h"
#include "polydem/scene/check_kinds/params.h"

namespace polydem::scene::kinds {

CheckKind freeMotion() {
  return {
      "free_motion",
      Quantity::kLength,
      "a statistic of the free blocks' motion, in its quantity's unit (m, m/s or rad/s); "
      "with at = \"first_below\" the time it first falls below `limit`, s",
      {word("quantity",
            {"mean_displacement", "max_displacement", "mean_speed", "max_speed",
             "max_angular_speed", "front_advance"},
            "what is measured", true),
       labelPrefix(false), direction("direction", false, "of the front (front_advance needs it)"),
       word("at", {"end", "max", "first_below"},
            "its value at the \"end\" (default), the \"max\" after `after`, or the "
            "\"first_below\" time"),
       number("after", false, Quantity::kTime, 0.0, kInf, false, false,
              "start of the window of max / first_below, s (default 0)"),
       number("every", false, Quantity::kDimensionless, 1.0, kInf, false, false,
              "steps between samples (default 1)"),
       measuredNumber("limit", "first_below: the value to fall below, in the quantity's unit")}};
}

}  // namespace polydem::scene::kinds
