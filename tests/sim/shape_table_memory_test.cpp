// The shape table of a cut rock mass, counted by part (geometry/shape_memory.h): on three joint
// sets at whole metres the free blocks are 1-m cubes, and those equal to the last bit in their
// body frames keep one polyhedron between them; each block keeps its own record and the joint
// plane of each face. Every part's bytes are asserted equal to what the counts of vertices, faces
// and edges give for exactly sized arrays, every shape's polyhedron is asserted to hold the same
// bits as the shape's own build (so sharing changes no kernel's input), and the sharing to be as
// far as equal bits allow. A jittered mass has no two equal blocks and keeps one polyhedron each.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <map>
#include <set>
#include <string>

#include "polydem/core/logging.h"
#include "polydem/geometry/shape_memory.h"
#include "polydem/geometry/shape_sharing.h"
#include "polydem/scene/scene_reader.h"
#include "polydem/sim/simulation.h"

namespace polydem::sim {
namespace {

const char* kMaterial = R"(
[scene]
id = "T-SHAPE-TABLE"
[simulation]
dt = "1e-4 s"
steps = 10
[[material]]
name = "rock"
density = "2600 kg/m^3"
kn = "10 GN/m"
ks = "5 GN/m"
friction_angle = 30
local_damping = 0.1
)";

// scripts/dev/scale-scene rock 4: a 4 m cube of rock, three orthogonal sets at 1 m, fixed base.
const char* kOrthogonal = R"(
[[rock_mass]]
name = "mass"
material = "rock"
region = { type = "box", min = [0, 0, 0], max = [4, 4, 4] }
[[rock_mass.plane]]
name = "base"
dip = 0
dip_direction = 0
point = [0, 0, 1]
fixed = "below"
[[rock_mass.joint_set]]
name = "J1"
dip = 90
dip_direction = 90
spacing = "1 m"
[[rock_mass.joint_set]]
name = "J2"
dip = 90
dip_direction = 0
spacing = "1 m"
[[rock_mass.joint_set]]
name = "J3"
dip = 0
dip_direction = 0
spacing = "1 m"
)";

const char* kJittered = R"(
[[rock_mass]]
name = "m"
material = "rock"
region = { type = "box", min = [0, 0, 0], max = [4, 4, 3] }
[[rock_mass.joint_set]]
name = "J1"
dip = 75
dip_direction = 260
spacing = "1.2 m"
spacing_jitter = 0.3
orientation_jitter = 6
seed = 4
[[rock_mass.joint_set]]
name = "J2"
dip = 80
dip_direction = 5
spacing = "1.5 m"
orientation_jitter = 4
seed = 5
)";

std::string sceneText(const char* mass) {
  std::string text = kMaterial;
  text += mass;
  return text;
}

std::map<std::string, std::uint64_t> bytesByPart(const particles::ShapeTable& shapes) {
  std::map<std::string, std::uint64_t> out;
  for (const auto& part : geometry::shapeMemory(shapes)) out[part.name] = part.bytes;
  return out;
}

// What each part must hold for exactly sized arrays, from the counts of the distinct polyhedra
// and of the shapes' faces.
std::map<std::string, std::uint64_t> bytesFromCounts(const particles::ShapeTable& shapes) {
  std::map<std::string, std::uint64_t> want;
  std::set<const geometry::ConvexPolyhedron*> seen;
  for (const auto& s : shapes) {
    const auto& p = *s.polyhedron;
    want["records"] += sizeof(geometry::BodyShape);
    want["face_planes"] += s.face_plane.size() * sizeof(std::int32_t);
    want["names"] += s.name.capacity() > 15 ? s.name.capacity() + 1 : 0;
    if (!seen.insert(&p).second) continue;
    const std::uint64_t v = p.vertices().size(), f = p.faces().size(), e = p.edges().size();
    std::uint64_t corners = 0;
    for (const auto& face : p.faces()) corners += face.vertices.size();
    want["polyhedra"] += sizeof(geometry::ConvexPolyhedron) + 16;
    want["vertices"] += v * sizeof(Vec3);
    want["faces"] += f * sizeof(geometry::Face);
    want["face_lists"] += 2 * corners * sizeof(int);  // a face's vertices and edges
    want["edges"] += e * sizeof(geometry::Edge);
    // Each vertex lists its edges, faces and neighbours (2 e entries each), and where its lists
    // begin (v + 1 entries).
    want["adjacency"] += (3 * 2 * e + v + 1) * sizeof(int);
    want["axes"] += (p.axisFaces().size() + p.axisEdges().size()) * sizeof(int);
  }
  return want;
}

std::size_t distinctPolyhedra(const particles::ShapeTable& shapes) {
  std::set<const geometry::ConvexPolyhedron*> seen;
  for (const auto& s : shapes) seen.insert(s.polyhedron.get());
  return seen.size();
}

// Each shape's polyhedron holds the bits the shape's own build gives; returns how many classes of
// equal bits the own builds fall into (the most sharing can do).
std::size_t expectSameAsOwnBuild(const setup::Setup& scene, const Simulation& sim) {
  const auto& specs = scene.shapes;
  EXPECT_EQ(specs.size(), sim.shapes().size());
  std::vector<geometry::ConvexPolyhedron> classes;
  for (std::size_t i = 0; i < specs.size() && i < sim.shapes().size(); ++i) {
    const auto own =
        geometry::toBodyFrame(geometry::ConvexPolyhedron::fromPoints(specs[i].vertices));
    const auto& p = *own.shape.polyhedron;
    EXPECT_TRUE(geometry::sameBits(p, *sim.shapes()[i].polyhedron))
        << "shape " << i << " '" << specs[i].name << "'";
    const bool seen = std::any_of(classes.begin(), classes.end(),
                                  [&](const auto& q) { return geometry::sameBits(p, q); });
    if (!seen) classes.push_back(p);
  }
  return classes.size();
}

TEST(ShapeTableMemory, CongruentCutBlocksShareTheirPolyhedra) {
  log::setLevel(log::Level::kWarning);
  const setup::Setup scene = scene::parseScene(sceneText(kOrthogonal), "orthogonal.toml");
  Simulation sim(scene, MPI_COMM_WORLD);
  const auto& shapes = sim.shapes();
  ASSERT_EQ(shapes.size(), 4u * 4u * 3u + 1u) << "48 free cubes and the fixed base";
  // Shared as far as the bits allow: some of the 1-m cubes, cut on planes at whole metres, are
  // equal to the last bit (they differ in which faces lie on joint planes, face_plane).
  const std::size_t classes = expectSameAsOwnBuild(scene, sim);
  EXPECT_EQ(distinctPolyhedra(shapes), classes);
  EXPECT_LT(classes, shapes.size());
  EXPECT_EQ(bytesByPart(shapes), bytesFromCounts(shapes));
  // Per block: its record and the joint plane of each of its 6 faces, besides its share of the
  // few polyhedra.
  EXPECT_EQ(bytesFromCounts(shapes).at("face_planes"), shapes.size() * 6 * sizeof(std::int32_t));
}

// What a rank holds per block of a cut mass for its shapes and its copy of the setup, from the
// counts: the shape table exactly sized (records, frames, the parts above), and the setup's
// particle and shape records without the shapes' vertex lists and face planes, which the shape
// table replaces (the caller's setup keeps them).
TEST(ShapeTableMemory, RockMassBytesPerBlockFromCounts) {
  log::setLevel(log::Level::kWarning);
  const setup::Setup scene = scene::parseScene(sceneText(kOrthogonal), "orthogonal.toml");
  Simulation sim(scene, MPI_COMM_WORLD);
  const std::uint64_t n = scene.shapes.size();
  ASSERT_EQ(n, scene.particles.size()) << "a shape of its own per block";
  std::uint64_t caller_lists = 0;
  for (const auto& spec : scene.shapes) {
    caller_lists += spec.vertices.size() + spec.face_planes.size();
  }
  EXPECT_GT(caller_lists, 0u) << "the caller's setup keeps its vertex lists";
  const auto& kept = sim.scene().shapes;
  ASSERT_EQ(kept.size(), n);
  for (std::size_t i = 0; i < n; ++i) {
    EXPECT_EQ(kept[i].name, scene.shapes[i].name);
    EXPECT_EQ(kept[i].vertices.capacity() + kept[i].face_planes.capacity(), 0u) << kept[i].name;
  }
  std::map<std::string, std::uint64_t> use;
  for (const auto& item : sim.memoryUse()) use[item.name] = item.bytes;
  std::uint64_t labels = 0;
  for (const auto& p : sim.scene().particles) {
    labels += p.label.capacity() > 15 ? p.label.capacity() + 1 : 0;
  }
  const std::uint64_t setup_bytes =
      n * (sizeof(setup::ParticleSpec) + sizeof(setup::ShapeSpec)) + labels;
  EXPECT_EQ(use.at("scene"), setup_bytes);
  std::uint64_t parts = 0;
  for (const auto& [name, bytes] : bytesFromCounts(sim.shapes())) parts += bytes;
  // Beyond the parts and the frames: one density per material.
  const std::uint64_t densities = scene.materials.size() * sizeof(double);
  EXPECT_GE(use.at("shapes"), parts + n * sizeof(ShapeFrame));
  EXPECT_LE(use.at("shapes"), parts + n * sizeof(ShapeFrame) + 2 * densities);
  const double per_block = static_cast<double>(use.at("scene") + use.at("shapes")) / n;
  const double from_counts = static_cast<double>(setup_bytes + parts + n * sizeof(ShapeFrame)) / n;
  EXPECT_NEAR(per_block, from_counts, 2.0 * densities / n);
  std::printf("per block on this rank: setup %.1f B, shapes %.1f B\n",
              static_cast<double>(use.at("scene")) / n, static_cast<double>(use.at("shapes")) / n);
}

TEST(ShapeTableMemory, JitteredBlocksKeepTheirOwnPolyhedra) {
  log::setLevel(log::Level::kWarning);
  const setup::Setup scene = scene::parseScene(sceneText(kJittered), "jittered.toml");
  Simulation sim(scene, MPI_COMM_WORLD);
  const auto& shapes = sim.shapes();
  ASSERT_GT(shapes.size(), 10u);
  EXPECT_EQ(expectSameAsOwnBuild(scene, sim), shapes.size());
  EXPECT_EQ(distinctPolyhedra(shapes), shapes.size());
  EXPECT_EQ(bytesByPart(shapes), bytesFromCounts(shapes));
}

TEST(ShapeTableMemory, PoolSharesOnlyTheSameBits) {
  const auto cube = geometry::ConvexPolyhedron::fromPoints(std::vector<Vec3>{
      {0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}, {0, 0, 1}, {1, 0, 1}, {0, 1, 1}, {1, 1, 1}});
  geometry::PolyhedronPool pool;
  const auto a = pool.share(std::make_shared<const geometry::ConvexPolyhedron>(cube));
  const auto b = pool.share(std::make_shared<const geometry::ConvexPolyhedron>(cube));
  EXPECT_EQ(a.get(), b.get());
  // The same cube moved: other vertices, not shared.
  const auto moved = pool.share(std::make_shared<const geometry::ConvexPolyhedron>(
      cube.transformed(Mat3::Identity(), Vec3(0.1, 0, 0))));
  EXPECT_NE(moved.get(), a.get());
  EXPECT_FALSE(geometry::sameBits(*moved, cube));
  EXPECT_EQ(pool.distinct(), 2u);
}

}  // namespace
}  // namespace polydem::sim
