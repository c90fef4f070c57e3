// Bodies a run cannot integrate and scenes it cannot hold: a sliver whose
// smallest principal moment is rounding noise, a mass that underflows, and particles placed on
// top of each other whose candidate pairs would not fit in memory, each an error naming the scene
// file and the particle's line instead of a time-step error, NaN positions or std::bad_alloc.
#include <gtest/gtest.h>

#include "polydem/core/error.h"
#include "polydem/core/strings.h"
#include "polydem/scene/scene_reader.h"
#include "polydem/sim/pair_memory.h"
#include "polydem/sim/simulation.h"

namespace polydem::sim {
namespace {

std::string scene(const std::string& shape, const std::string& density, const std::string& more) {
  return cat("[scene]\nid = \"T-BAD-BODIES\"\n[simulation]\ndt = 1e-6\nsteps = 2\n",
             "[[material]]\nname = \"rock\"\ndensity = ", density, "\nkn = 1e9\n",
             "[[shape]]\nname = \"s\"\n", shape, "[[particle]]\nshape = \"s\"\n",
             "material = \"rock\"\nposition = [0, 0, 10]\n", more);
}

/// The InputError building a Simulation of `text` raises, with its line; fails if none.
std::pair<int, std::string> errorOf(const std::string& text) {
  try {
    Simulation sim(scene::parseScene(text, "bad.toml"), MPI_COMM_WORLD);
  } catch (const InputError& e) {
    return {e.line(), e.what()};
  }
  ADD_FAILURE() << "no error for:\n" << text;
  return {0, ""};
}

TEST(BadBodies, ASliverIsRefusedAtTheParticle) {
  // A needle 3.7 m long and about 1e-8 m across.
  const auto [line, message] = errorOf(scene(
      "type = \"vertices\"\nvertices = [[0, 0, 0], [3, 1, 2], [2e-8, 1e-8, 0], [0, 1e-8, 1e-8]]\n",
      "2500", ""));
  EXPECT_EQ(line, 14) << message;  // the [[particle]] line
  EXPECT_NE(message.find("shape 's' is too thin"), std::string::npos) << message;
  // A thin plate is fine: only the smallest moment of a needle vanishes.
  EXPECT_NO_THROW(Simulation(
      scene::parseScene(scene("type = \"box\"\nsize = [1, 1, 1e-4]\n", "2500", ""), "ok.toml"),
      MPI_COMM_WORLD));
}

TEST(BadBodies, AMassThatUnderflowsIsRefused) {
  const auto [line, message] = errorOf(scene("type = \"cube\"\nedge = \"10 um\"\n", "1e-300", ""));
  EXPECT_EQ(line, 14) << message;
  EXPECT_NE(message.find("has mass"), std::string::npos) << message;
  EXPECT_NE(message.find("not a usable number"), std::string::npos) << message;
}

// The circumradius of each particle of the simulation's storage.
std::vector<double> radiiOf(const Simulation& sim) {
  std::vector<double> radii;
  for (std::size_t i = 0; i < sim.particles().size(); ++i) {
    radii.push_back(sim.shapes()[sim.particles()[i].shape].circumradius);
  }
  return radii;
}

TEST(BadBodies, CoincidentParticlesThatWouldNotFitInMemory) {
  // 27 cubes within 1e-9 m of each other: 351 candidate pairs.
  const std::string text =
      scene("type = \"cube\"\nedge = 1\n", "2500",
            "[[particle_grid]]\nshape = \"s\"\nmaterial = \"rock\"\nspacing = 1e-9\n"
            "count = [3, 3, 3]\norigin = [5, 5, 5]\n");
  const setup::Setup sc = scene::parseScene(text, "coincident.toml");
  const Simulation sim(sc, MPI_COMM_WORLD);
  // The guard's inputs as the broad phase of the first step would give them.
  std::vector<broadphase::CandidatePair> pairs;
  const auto& storage = sim.particles();
  for (std::size_t i = 0; i < storage.size(); ++i) {
    for (std::size_t j = i + 1; j < storage.size(); ++j) {
      if ((storage[i].position - storage[j].position).norm() < 1e-6) {
        pairs.push_back({static_cast<std::int32_t>(i), static_cast<std::int32_t>(j)});
      }
    }
  }
  if (storage.localCount() < 27) GTEST_SKIP() << "the grid is split over ranks";
  ASSERT_EQ(pairs.size(), 351u);
  const std::vector<double> radii = radiiOf(sim);
  EXPECT_FALSE(pairMemoryProblem(sc, storage, radii, 0.0, pairs, 0, 1 << 30));
  const auto problem = pairMemoryProblem(sc, storage, radii, 0.0, pairs, 0, 1000);
  ASSERT_TRUE(problem);
  EXPECT_NE(problem->find("coincident.toml:"), std::string::npos) << *problem;
  EXPECT_NE(problem->find("351 candidate pairs would need about"), std::string::npos) << *problem;
  EXPECT_NE(problem->find("has 26 candidate partners"), std::string::npos) << *problem;
  EXPECT_NE(problem->find("particles placed on top of each other"), std::string::npos) << *problem;
}

// Cubes 100 m apart, none touching another, but a contact margin of kilometres (contact_margin
// times a free 20 km block's circumradius) makes every pair a candidate: the message blames the
// margin, not overlapping particles.
TEST(BadBodies, AHugeMarginIsNamedNotOverlaps) {
  const std::string text =
      scene("type = \"cube\"\nedge = 1\n", "2500",
            "[[particle_grid]]\nshape = \"s\"\nmaterial = \"rock\"\nspacing = 100\n"
            "count = [3, 3, 3]\norigin = [0, 0, 0]\n");
  setup::Setup sc = scene::parseScene(text, "margin.toml");
  sc.contact_margin = 1.0;
  setup::ShapeSpec big = sc.shapes[0];
  big.name = "big";
  for (Vec3& v : big.vertices) v *= 20000.0;
  sc.shapes.push_back(big);
  setup::ParticleSpec far = sc.particles.back();
  far.uid = static_cast<Uid>(sc.particles.size() + 1);
  far.shape = static_cast<int>(sc.shapes.size() - 1);
  far.position = Vec3(30000.0, 0, 0);
  far.label.clear();
  sc.particles.push_back(far);
  const Simulation sim(sc, MPI_COMM_WORLD);
  const auto& storage = sim.particles();
  if (storage.localCount() < storage.size()) GTEST_SKIP() << "split over ranks";
  const std::vector<double> radii = radiiOf(sim);
  const double margin = 1.0 * radii.back();
  std::vector<broadphase::CandidatePair> pairs;
  for (std::size_t i = 0; i < storage.size(); ++i) {
    for (std::size_t j = i + 1; j < storage.size(); ++j) {
      const double d = (storage[i].position - storage[j].position).norm();
      if (d <= radii[i] + radii[j] + margin) {
        const bool lower = storage[i].uid < storage[j].uid;
        pairs.push_back(
            {static_cast<std::int32_t>(lower ? i : j), static_cast<std::int32_t>(lower ? j : i)});
      }
    }
  }
  ASSERT_EQ(pairs.size(), storage.size() * (storage.size() - 1) / 2);  // every pair
  const auto problem = pairMemoryProblem(sc, storage, radii, margin, pairs, 0, 1000);
  ASSERT_TRUE(problem);
  EXPECT_EQ(problem->find("overlap massively"), std::string::npos) << *problem;
  EXPECT_NE(problem->find("no particle overlaps it"), std::string::npos) << *problem;
  EXPECT_NE(problem->find("the pairs come from the contact margin of"), std::string::npos)
      << *problem;
  EXPECT_NE(problem->find("contact_margin = 1 times"), std::string::npos) << *problem;
}

}  // namespace
}  // namespace polydem::sim
