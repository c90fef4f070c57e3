// Comparing two scene texts for a restart (scene_reader.h): as TOML trees, so that comments,
// spacing and key order do not count, but every value does.
#include <toml++/toml.h>
#include <set>

#include "polydem/core/error.h"
#include "polydem/scene/scene_reader.h"

namespace polydem::scene {

namespace {

toml::table parseOrThrow(std::string_view text, const std::string& name) {
  try {
    return toml::parse(text, name);
  } catch (const toml::parse_error& e) {
    throw InputError(name, static_cast<int>(e.source().begin.line), std::string(e.description()));
  }
}

// The settings a continued run may change.
void dropStopSettings(toml::table& scene) {
  scene.erase("output");
  scene.erase("checkpoint");
  if (toml::table* sim = scene["simulation"].as_table()) {
    sim->erase("end_time");
    sim->erase("steps");
  }
  // The kernel's algorithm switch, so that a run written before the separating-axis test
  // continues to the same bits with separating_axes = false (docs/kernels/gjk-epa.md).
  if (toml::table* params = scene["kernel_params"].as_table()) {
    params->erase("separating_axes");
    if (params->empty()) scene.erase("kernel_params");
  }
}

}  // namespace

std::string sceneDifference(std::string_view stored, const std::string& stored_name,
                            std::string_view given, const std::string& given_name) {
  toml::table a = parseOrThrow(stored, stored_name);
  toml::table b = parseOrThrow(given, given_name);
  dropStopSettings(a);
  dropStopSettings(b);
  std::set<std::string> keys;
  for (const auto& [k, v] : a) keys.insert(std::string(k.str()));
  for (const auto& [k, v] : b) keys.insert(std::string(k.str()));
  for (const std::string& key : keys) {
    const toml::node* na = a.get(key);
    const toml::node* nb = b.get(key);
    const bool array_of_tables =
        (na && na->is_array_of_tables()) || (nb && nb->is_array_of_tables());
    const std::string label = array_of_tables ? "[[" + key + "]]" : "[" + key + "]";
    if (!na || !nb) return label + (na ? " is missing" : " was added");
    const toml::table* ta = na->as_table();
    const toml::table* tb = nb->as_table();
    if (ta && tb) {  // name the key within the table
      std::set<std::string> inner;
      for (const auto& [k, v] : *ta) inner.insert(std::string(k.str()));
      for (const auto& [k, v] : *tb) inner.insert(std::string(k.str()));
      for (const std::string& k : inner) {
        toml::table x, y;
        if (const toml::node* n = ta->get(k)) x.insert(k, *n);
        if (const toml::node* n = tb->get(k)) y.insert(k, *n);
        if (!(x == y)) return label + " " + k;
      }
      continue;
    }
    toml::table x, y;
    x.insert(key, *na);
    y.insert(key, *nb);
    if (!(x == y)) return label;
  }
  return {};
}

}  // namespace polydem::scene
