// [[operator]]: a user force operator named in the scene (docs/scene-format.md "Operators"). The
// reader checks the names and resolves the library's path; the simulation loads the library and
// puts the operators into the step (sim/scene_operators.h), where an unknown name or a library
// that does not load fails at this section's line.
#include <cctype>
#include <filesystem>
#include <string>

#include "polydem/scene/scene_sections.h"

namespace polydem::scene::detail {

namespace {

// The library exports the operator as a C function named after it (sim/operator_library.h), so
// the name must be a C identifier.
bool isIdentifier(const std::string& name) {
  if (name.empty() || std::isdigit(static_cast<unsigned char>(name.front()))) return false;
  for (char c : name) {
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_') return false;
  }
  return true;
}

// Relative to the scene file's folder (a scene parsed from a string, "<...>", resolves against the
// working directory), so that a scene and its library move together. The path always has a
// folder ("./libx.so"): a bare name would make dlopen search the system's library path instead.
std::string libraryPath(const Section& s, const std::string& name) {
  const std::filesystem::path given(name);
  if (given.is_absolute()) return name;
  const std::string& scene_file = s.context().file();
  std::filesystem::path folder = scene_file.empty() || scene_file.front() == '<'
                                     ? std::filesystem::path()
                                     : std::filesystem::path(scene_file).parent_path();
  if (folder.empty()) folder = ".";
  return (folder / given).string();
}

}  // namespace

void readOperators(const Context& ctx, const toml::table& root, setup::Setup& scene) {
  for (const Section& s : entries(ctx, root, "operator", "name")) {
    s.allowOnly({"name", "library"});
    setup::OperatorSpec op;
    op.name = s.requiredString("name");
    op.line = s.line();
    if (!isIdentifier(op.name)) {
      s.fail("name", "'" + op.name + "' is not a C identifier (letters, digits, _)");
    }
    if (indexByName(scene.operators, op.name) >= 0) {
      s.fail("name", "another [[operator]] is named '" + op.name + "'");
    }
    if (const auto library = s.string("library")) {
      if (library->empty()) s.fail("library", "is empty");
      op.library = libraryPath(s, *library);
    }
    scene.operators.push_back(std::move(op));
  }
}

}  // namespace polydem::scene::detail
