// The registry of check kinds: kind name -> the factory that builds its Check (checks.h), as
// contact/kernel_list.inc is for kernels. The built-in kinds (checks/check_table.cpp) are the
// ones the scene reader declares (scene/check_kinds/); run_check_kinds asserts both lists agree. A
// C++ program adds its own kind with registerCheckKind() and puts a CheckSpec of that kind into
// the setup it builds (the scene reader accepts declared kinds only).
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "polydem/run/checks.h"

namespace polydem::run {

/// Builds the check for `spec`; throws InputError (the check's line) for a bad parameter.
using CheckFactory = std::function<std::unique_ptr<Check>(
    const setup::Setup& scene, const setup::CheckSpec& spec, Tracker& tracker)>;

/// Adds a kind; throws polydem::Error if `kind` is empty or already registered.
void registerCheckKind(std::string kind, CheckFactory factory);
/// The factory of `kind`, or nullptr.
const CheckFactory* findCheckFactory(std::string_view kind);
/// Every registered kind: the built-in ones first, in docs/scene-format.md's order.
std::vector<std::string> registeredCheckKinds();

}  // namespace polydem::run
