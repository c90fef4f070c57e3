// The scene's [[operator]]s loaded and bound by name (scene_operators.h).
#include "polydem/sim/scene_operators.h"

#include <dlfcn.h>

#include <memory>

#include "polydem/core/error.h"
#include "polydem/core/strings.h"
#include "polydem/sim/operator_library.h"
#include "polydem/sim/step/step_list.h"

namespace polydem::sim {

namespace {

// The library stays loaded while an operator from it is held (the handle is shared by them).
using Library = std::shared_ptr<void>;

Library openLibrary(const setup::Setup& scene, const setup::OperatorSpec& spec) {
  void* handle = dlopen(spec.library.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (!handle) {
    const char* why = dlerror();
    throw InputError(scene.file, spec.line,
                     cat("[[operator]] '", spec.name, "': library '", spec.library,
                         "' does not load: ", why ? why : "unknown reason"));
  }
  return Library(handle, [](void* h) { dlclose(h); });
}

ForceOperator libraryOperator(const setup::Setup& scene, const setup::OperatorSpec& spec,
                              const Library& library) {
  const std::string symbol = kOperatorSymbolPrefix + spec.name;
  void* address = dlsym(library.get(), symbol.c_str());
  if (!address) {
    throw InputError(scene.file, spec.line,
                     cat("[[operator]] '", spec.name, "': library '", spec.library,
                         "' defines no operator of that name (no POLYDEM_FORCE_OPERATOR(",
                         spec.name, "), exported symbol ", symbol, ")"));
  }
  const auto run = reinterpret_cast<LibraryOperator>(address);
  return [run, library](const ForceStep& step) { run(step); };
}

ForceOperator hostOperator(const setup::Setup& scene, const setup::OperatorSpec& spec,
                           const HostOperators& host) {
  const auto it = host.find(spec.name);
  if (it == host.end() || !it->second) {
    throw InputError(scene.file, spec.line,
                     cat("[[operator]] '", spec.name, "' names no library, and the program ",
                         "running the scene supplies no operator of that name (give library = ",
                         "\"...\", or run the scene from Python with Simulation(scene, ",
                         "operators={'", spec.name, "': fn}))"));
  }
  return it->second;
}

}  // namespace

std::vector<NamedForceOperator> sceneOperators(const setup::Setup& scene,
                                               const HostOperators& host) {
  for (const auto& [name, op] : host) {
    bool named = false;
    for (const auto& spec : scene.operators) named = named || spec.name == name;
    if (!named) {
      throw Error(cat("operator '", name, "' is supplied, but scene ", scene.file,
                      " names no [[operator]] '", name, "' (add it to the scene, or add it in ",
                      "code with add_force_operator)"));
    }
  }
  std::vector<NamedForceOperator> ops;
  for (const auto& spec : scene.operators) {
    if (isStepOperator(spec.name)) {
      throw InputError(scene.file, spec.line,
                       cat("[[operator]] '", spec.name, "' has the name of an operator of the ",
                           "step; give it a name of its own (it is also its timer's)"));
    }
    ForceOperator op = spec.library.empty()
                           ? hostOperator(scene, spec, host)
                           : libraryOperator(scene, spec, openLibrary(scene, spec));
    ops.push_back({spec.name, std::move(op)});
  }
  return ops;
}

}  // namespace polydem::sim
