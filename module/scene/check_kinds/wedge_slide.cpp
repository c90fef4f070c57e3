// The declaration of check kind "wedge_slide": its value's unit and its parameters (computed by
// module/run/checks/wedge_slide.cpp). A frictionless wedge against Zhao eq. 45.
#include "polydem/scene/check_kinds/kinds.h"
#include "polydem/scene/check_kinds/params.h"

namespace polydem::scene::kinds {

CheckKind wedgeSlide() {
  return {"wedge_slide",
          Quantity::kDimensionless,
          "largest |numerical - analytical| travel over the final analytical travel (Zhao eq. 45)",
          {particle(), theta(false), gravity(),
           direction("direction", true, "down the intersection line")}};
}

}  // namespace polydem::scene::kinds
