// The sections of a scene file, each read by one function. Internal to the scene reader:
// scene_reader.cpp reads the run settings, scene_bodies.cpp the shapes and particles,
// scene_checks.cpp the expected results.
#pragma once

#include <toml++/toml.h>

#include "io/scene.h"
#include "io/toml_values.h"

namespace polydem::io::detail {

/// [[shape]]: each resolved to the vertices of its convex hull.
void readShapes(const Context& ctx, const toml::table& root, Scene& scene);
/// [[particle]] and [[particle_grid]], in file order; needs shapes, materials and drivers.
void readParticles(const Context& ctx, const toml::table& root, Scene& scene);
/// [[check]], each against its kind's declared parameters (io/check_kinds.h); needs particles.
void readChecks(const Context& ctx, const toml::table& root, Scene& scene);

/// Refuses, at `key` of `s`, a scene of `particles` particles that cannot fit in the memory
/// available (core/memory.h), before they are made.
void checkParticleMemory(const Section& s, std::string_view key, std::uint64_t particles);

/// Index of the entry called `name` in `items` (by their .name), or -1.
template <typename T>
int indexByName(const std::vector<T>& items, const std::string& name) {
  for (std::size_t i = 0; i < items.size(); ++i) {
    if (items[i].name == name) return static_cast<int>(i);
  }
  return -1;
}

}  // namespace polydem::io::detail
