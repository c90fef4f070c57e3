// The declaration of check kind "separation_time": its value's unit and its parameters (computed by
// module/run/checks/separation_time.cpp). When a particle first has no contact left.
#include "polydem/scene/check_kinds/kinds.h"
#include "polydem/scene/check_kinds/params.h"

namespace polydem::scene::kinds {

CheckKind separationTime() {
  return {"separation_time",
          Quantity::kTime,
          "first time the particle, once in contact, has none, s",
          {particle()}};
}

}  // namespace polydem::scene::kinds
