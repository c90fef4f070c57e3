// Deliberately wrong: code of module high declared in module low's namespace, and a name of low
// re-exported as high's (check-layout must report both).
#pragma once

namespace polydem::low {
struct Widget {};
}  // namespace polydem::low

namespace polydem::high {
using low::Widget;
using Gadget = polydem::low::Widget;
}  // namespace polydem::high
