// The declaration of check kind "tilt_failure": its value's unit and its parameters (computed by
// module/run/checks/tilt_failure.cpp). The tilt at which blocks on a tilting platform fail (a
// rock-slope kind).
#include "polydem/scene/check_kinds/kinds.h"
#include "polydem/scene/check_kinds/params.h"

namespace polydem::scene::kinds {

CheckKind tiltFailure() {
  return {
      "tilt_failure",
      Quantity::kAngle,
      "the platform's tilt when a block first moves `threshold` against it, deg; with measure = "
      "\"rotation\", the slope's turn when a block first moves `reach`: the mass-weighted "
      "median turn against the platform of the blocks that have moved reach / 10",
      {labelPrefix(true),
       {"platform",
        CheckParamType::kParticle,
        true,
        {},
        -kInf,
        kInf,
        false,
        false,
        {},
        "the tilting body"},
       word("measure", {"angle", "rotation"}, "\"angle\" (the tilt; default) or \"rotation\""),
       number("threshold", false, Quantity::kLength, 0.0, kInf, true, false,
              "tilt: displacement against the platform that counts as failure, m"),
       number("reach", false, Quantity::kLength, 0.0, kInf, true, false,
              "rotation: displacement of the first block at which the slope's turn is read, m")}};
}

}  // namespace polydem::scene::kinds
