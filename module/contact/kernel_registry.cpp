// The table of contact kernels by name. Each kernel file provides a factory; adding a kernel is one
// line here. Names are what scene files, benchmarks and the command line use.
#include <algorithm>

#include "polydem/contact/contact.h"
#include "polydem/contact/kernel_factories.h"
#include "polydem/core/error.h"
#include "polydem/core/strings.h"

namespace polydem::contact {

namespace {
struct Entry {
  const char* name;
  std::unique_ptr<Kernel> (*make)(const KernelParams&);
};

const std::vector<Entry>& registry() {
  static const std::vector<Entry> entries = {
#define POLYDEM_KERNEL(name, factory) {name, &factory},
#include "polydem/contact/kernel_list.inc"
#undef POLYDEM_KERNEL
  };
  return entries;
}
}  // namespace

std::vector<std::string> kernelNames() {
  std::vector<std::string> names;
  for (const auto& e : registry()) names.emplace_back(e.name);
  return names;
}

std::unique_ptr<Kernel> makeKernel(std::string_view name, const KernelParams& params) {
  for (const auto& e : registry()) {
    if (name == e.name) return e.make(params);
  }
  throw Error(
      cat("unknown contact kernel '", name, "'; known kernels: ", join(kernelNames(), ", ")));
}

}  // namespace polydem::contact
