// The sections of a scene file, each read by one function. Internal to the scene reader:
// scene_reader.cpp reads the run settings, scene_bodies.cpp the shapes and particles,
// scene_checks.cpp the expected results.
#pragma once

#include <toml++/toml.h>

#include "polydem/scene/toml_values.h"
#include "polydem/setup/setup.h"

namespace polydem::scene::detail {

/// [[shape]]: each resolved to the vertices of its convex hull.
void readShapes(const Context& ctx, const toml::table& root, setup::Setup& scene);
/// [[particle]], [[particle_grid]] and [[rock_mass]], in file order; needs shapes, materials and
/// drivers.
void readParticles(const Context& ctx, const toml::table& root, setup::Setup& scene);
/// [[check]], each against its kind's declared parameters (check_kinds.h); needs particles.
void readChecks(const Context& ctx, const toml::table& root, setup::Setup& scene);

/// Refuses, at `key` of `s`, a scene of `particles` particles that cannot fit in the memory
/// available (core/memory.h), before they are made.
void checkParticleMemory(const Section& s, std::string_view key, std::uint64_t particles);

/// One [[rock_mass]] cut into blocks, before they become shapes and particles.
struct RockMassCut {
  geometry::RockMass mass;
  setup::RockMassInfo info;  // first_uid and blocks are filled in by the particle reader
  int material = -1, fixed_material = -1;
  std::vector<int> plane_joint;  // per plane of `mass`: its [[joint]], -1: none
};

/// The joint planes the faces of `block` lie on (their indices offset by `first_plane`, the
/// index of the mass's first plane in Setup::joint_planes).
std::vector<setup::FacePlane> blockFacePlanes(const geometry::RockMass& mass,
                                              const geometry::RockBlock& block, int first_plane);

/// [[joint]] (scene_joints.cpp), before the rock masses that refer to them.
void readJoints(const Context& ctx, const toml::table& root, setup::Setup& scene);
/// The [[joint]] named by `key` of `s` (its index), -1 if `s` has no such key; fails for a name
/// that no [[joint]] has.
int jointReference(const Section& s, std::string_view key, const setup::Setup& scene);
/// Reads and cuts one [[rock_mass]] (scene_rock_mass.cpp); needs the materials.
RockMassCut readRockMass(const Section& s, const setup::Setup& scene);

/// [fos] (scene_fos.cpp); needs the materials.
void readFos(const Context& ctx, const toml::table& root, setup::Setup& scene);

/// [water] (scene_water.cpp).
void readWater(const Context& ctx, const toml::table& root, setup::Setup& scene);

/// [seismic] (scene_seismic.cpp); needs [simulation] gravity.
void readSeismic(const Context& ctx, const toml::table& root, setup::Setup& scene);
/// The acceleration record of [seismic] (scene_ground_record.cpp) into `seismic`, in m/s^2;
/// false when `s` names none.
bool readGroundRecord(const Section& s, const setup::Setup& scene, setup::SeismicSpec& seismic);

/// [[bolt]] (scene_bolts.cpp); the blocks they cross are found by the simulation.
void readBolts(const Context& ctx, const toml::table& root, setup::Setup& scene);

/// [[operator]] (scene_operators.cpp): names only; the simulation loads them.
void readOperators(const Context& ctx, const toml::table& root, setup::Setup& scene);

/// Index of the entry called `name` in `items` (by their .name), or -1.
template <typename T>
int indexByName(const std::vector<T>& items, const std::string& name) {
  for (std::size_t i = 0; i < items.size(); ++i) {
    if (items[i].name == name) return static_cast<int>(i);
  }
  return -1;
}

}  // namespace polydem::scene::detail
