// polydem bench contact-model: what sub-contacts cost. The contact phase of the same scenes with
// contact_model = "sub-contacts" and "point", measured in turns (A B A B ...) in one process, so
// that each ratio compares the two models at the same moment of a shared, noisy machine. Scenes:
// the dense pack of cubes (every face in contact) and the main job's rock slide.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>
#include <vector>

#include "commands.h"
#include "generators/pile_scene.h"
#include "polydem/core/error.h"
#include "polydem/core/logging.h"
#include "polydem/core/mpi_env.h"
#include "polydem/core/strings.h"
#include "polydem/scene/scene_reader.h"
#include "polydem/sim/simulation.h"

namespace polydem::app {

namespace {

struct Timed {
  double contact_ms = 0.0;  // contact phase per step, this rank, median over the rounds
  double step_ms = 0.0;     // whole step per step
  std::int64_t contacts = 0, subcontacts = 0;
};

// One round: `warmup` steps, then `steps` timed ones; the contact phase from the timing pool.
Timed round(const setup::Setup& scene, std::int64_t warmup, std::int64_t steps) {
  sim::Simulation sim(scene, MPI_COMM_WORLD);
  for (std::int64_t i = 0; i < warmup; ++i) sim.step();
  sim.loop().timing().clear();
  for (std::int64_t i = 0; i < steps; ++i) sim.step();
  Timed t;
  for (const auto& e : sim.loop().timing().entries()) {
    t.step_ms += 1e3 * e.seconds / static_cast<double>(steps);
    if (e.name == "contacts") t.contact_ms = 1e3 * e.seconds / static_cast<double>(steps);
  }
  t.contacts = sim.monitors().contacts;
  t.subcontacts = mpi::allreduceSum(sim.contactStats().subcontacts, MPI_COMM_WORLD);
  t.contact_ms = mpi::allreduceMax(t.contact_ms, MPI_COMM_WORLD);
  t.step_ms = mpi::allreduceMax(t.step_ms, MPI_COMM_WORLD);
  return t;
}

double medianSeconds(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

nlohmann::json compare(const std::string& name, setup::Setup scene, std::int64_t warmup,
                       std::int64_t steps, int rounds) {
  std::vector<double> contact[2], step[2];
  Timed last[2];
  const char* models[2] = {"point", "sub-contacts"};
  for (int r = 0; r < rounds; ++r) {
    for (int m = 0; m < 2; ++m) {
      scene.contact_model = models[m];
      last[m] = round(scene, warmup, steps);
      contact[m].push_back(last[m].contact_ms);
      step[m].push_back(last[m].step_ms);
    }
  }
  const double c0 = medianSeconds(contact[0]), c1 = medianSeconds(contact[1]);
  const double s0 = medianSeconds(step[0]), s1 = medianSeconds(step[1]);
  if (mpi::rank() == 0) {
    std::printf("%-34s %9lld %12lld %11.3f %11.3f %7.2fx %10.3f %10.3f %7.2fx\n", name.c_str(),
                static_cast<long long>(last[1].contacts),
                static_cast<long long>(last[1].subcontacts), c0, c1, c1 / c0, s0, s1, s1 / s0);
  }
  return {{"scene", name},
          {"contacts", last[1].contacts},
          {"subcontacts", last[1].subcontacts},
          {"contact_ms_point", c0},
          {"contact_ms_subcontacts", c1},
          {"contact_ratio", c1 / c0},
          {"step_ms_point", s0},
          {"step_ms_subcontacts", s1},
          {"step_ratio", s1 / s0}};
}

}  // namespace

int benchContactModel(int argc, char** argv) {
  Args args(argc, argv, {"help"});
  if (args.flag("help")) {
    std::printf(
        "usage: [mpirun -n P] polydem bench contact-model [--particles N] [--steps S]\n"
        "         [--rounds R] [--kernel NAME] [--demo SCENE.toml] [--json FILE]\n"
        "  the contact phase per step with contact_model = point and sub-contacts, in turns:\n"
        "  a dense pack of N cubes (default 8000, every face in contact) and the demo rock\n"
        "  slide (default benchmark_scenes/demo-rockslide.toml, 2,000 steps in, while it\n"
        "  slides); medians over R rounds (default 3) of S timed steps (default 20 and 1000).\n");
    return 0;
  }
  sim::PileOptions pile;
  pile.particles = args.integer("particles", 8000, 1);
  pile.shapes = "cubes";
  pile.gap = -0.001;
  pile.kernel = args.value("kernel", "gjk-epa-ipm");
  const std::int64_t steps = args.integer("steps", 20, 1, Args::kInt64Max);
  const int rounds = static_cast<int>(args.integer("rounds", 3, 1));
  const std::string demo = args.value("demo", "benchmark_scenes/demo-rockslide.toml");
  const auto json_path = args.value("json");
  args.rejectUnknown();
  log::setLevel(log::Level::kWarning);

  if (mpi::rank() == 0) {
    std::printf("contact phase per step, %d rank(s), kernel %s, medians of %d rounds\n",
                mpi::size(), pile.kernel.c_str(), rounds);
    std::printf("%-34s %9s %12s %11s %11s %8s %10s %10s %8s\n", "scene", "contacts", "subcontacts",
                "point ms", "sub ms", "ratio", "step pt", "step sub", "ratio");
  }
  nlohmann::json out = nlohmann::json::array();
  out.push_back(compare(cat("dense pack, ", pile.particles, " cubes"), sim::makePileScene(pile), 5,
                        steps, rounds));
  setup::Setup rockslide = scene::readScene(demo);
  rockslide.kernel = pile.kernel;
  out.push_back(
      compare("demo rock slide (" + rockslide.id + ")", rockslide, 2000, 50 * steps, rounds));
  if (json_path && mpi::rank() == 0) {
    std::ofstream(*json_path) << out.dump(2) << "\n";
    std::printf("written: %s\n", json_path->c_str());
  }
  return 0;
}

}  // namespace polydem::app
