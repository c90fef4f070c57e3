// Reads a scene file (TOML, format in docs/scene-format.md) into an setup::Setup.
//
// Every value may carry a unit ("1.5e8 N/m", "30 deg"); the reader checks structure, types,
// units, references between sections and value ranges, and throws an InputError "file:line:
// message" for the first problem it finds. Checks that need the kernel or the physics (a kernel
// that needs a penalty, a time step too large for the stiffness) are left to the simulation.
#pragma once

#include <string>
#include <string_view>

#include "polydem/setup/setup.h"

namespace polydem::scene {

/// The text of the scene file at `path` (InputError if it cannot be read).
std::string readSceneText(const std::string& path);

/// Reads and checks the scene file at `path`.
setup::Setup readScene(const std::string& path);

/// Parses scene text; `name_for_messages` is the file name errors and Setup::file carry.
setup::Setup parseScene(std::string_view text, const std::string& name_for_messages);

/// Empty if two scene texts describe the same run up to its stop settings ([simulation] end_time
/// and steps), its [output] and [checkpoint] tables and [kernel_params] separating_axes, which may
/// change when a run continues from a checkpoint; otherwise the first table or key that differs,
/// e.g. "[simulation] dt" or
/// "[[particle]]". Throws InputError if either text is not TOML.
std::string sceneDifference(std::string_view stored, const std::string& stored_name,
                            std::string_view given, const std::string& given_name);

}  // namespace polydem::scene
