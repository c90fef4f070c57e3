// polydem bench scaling: strong scaling of a P-PILE scene. The same run measures the scene on
// 1 rank and on larger groups of the launched ranks (the others wait), so every figure has its
// 1-rank peer from the same machine and the same moment.
#include <chrono>
#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "commands.h"
#include "core/error.h"
#include "core/logging.h"
#include "core/mpi_env.h"
#include "core/strings.h"
#include "sim/pile_scene.h"
#include "sim/simulation.h"

namespace polydem::app {

namespace {

struct Measurement {
  int ranks = 0;
  double seconds = 0.0;  // timed steps only
  std::int64_t steps = 0, particles = 0, contacts = 0;
  double step_ms_min = 0, step_ms_mean = 0, step_ms_max = 0;  // per-rank loop time per step
  double broadphase_share = 0.0, contact_share = 0.0, comm_share = 0.0;
};

std::vector<int> parseRanks(const std::string& text, int world) {
  std::vector<int> out;
  if (text.empty()) {
    for (int r = 1; r < world; r *= 2) out.push_back(r);
    out.push_back(world);
    return out;
  }
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) {
    const int r = std::stoi(item);
    if (r < 1 || r > world) throw UsageError(cat("--ranks: ", r, " is not in 1..", world));
    out.push_back(r);
  }
  return out;
}

Measurement measure(const io::Scene& scene, MPI_Comm comm, std::int64_t warmup,
                    std::int64_t steps) {
  sim::Simulation sim(scene, comm);
  for (std::int64_t i = 0; i < warmup; ++i) sim.step();
  sim.loop().timing().clear();
  MPI_Barrier(comm);
  const auto t0 = std::chrono::steady_clock::now();
  for (std::int64_t i = 0; i < steps; ++i) sim.step();
  MPI_Barrier(comm);
  const auto t1 = std::chrono::steady_clock::now();
  Measurement m;
  m.ranks = mpi::size(comm);
  m.seconds = std::chrono::duration<double>(t1 - t0).count();
  m.steps = steps;
  const auto mon = sim.monitors();
  m.particles = mon.particles;
  m.contacts = mon.contacts;
  // Per-rank loop time per step: the sum of the rank's timers.
  double mine = 0.0;
  for (const auto& e : sim.loop().timing().entries()) mine += e.seconds;
  const double per_step = 1e3 * mine / static_cast<double>(steps);
  m.step_ms_min = mpi::allreduceMin(per_step, comm);
  m.step_ms_max = mpi::allreduceMax(per_step, comm);
  double sum = 0.0;
  MPI_Allreduce(&per_step, &sum, 1, MPI_DOUBLE, MPI_SUM, comm);
  m.step_ms_mean = sum / m.ranks;
  for (const auto& r : sim.loop().timing().reduce(comm)) {
    if (r.name == "broadphase") m.broadphase_share = r.share;
    if (r.name == "contacts") m.contact_share = r.share;
    if (r.name == "communicate") m.comm_share = r.share;
  }
  return m;
}

}  // namespace

int benchScaling(int argc, char** argv) {
  Args args(argc, argv, {"help"});
  if (args.flag("help")) {
    std::printf(
        "usage: mpirun -n P polydem bench scaling [--particles N] [--shapes mixed|cubes]\n"
        "         [--steps S] [--warmup W] [--kernel NAME] [--ranks 1,2,...] [--json FILE]\n"
        "         [--gap G]   lattice gap relative to the size (default 0.05: particles start\n"
        "                     apart and fall; -0.001 with cubes: a dense pack, every face in\n"
        "                     contact from the first step)\n"
        "  runs the P-PILE scene on 1 rank and on groups of the P launched ranks (default 1, 2,\n"
        "  4, ..., P) and prints particle-steps per second per core and parallel efficiency.\n");
    return 0;
  }
  sim::PileOptions pile;
  pile.particles = args.integer("particles", 20000);
  pile.shapes = args.value("shapes", "mixed");
  pile.kernel = args.value("kernel", "gjk-epa-ipm");
  pile.layers = args.integer("layers", 10);
  pile.gap = args.number("gap", pile.gap);
  const std::int64_t steps = args.integer("steps", 100);
  const std::int64_t warmup = args.integer("warmup", 20);
  const auto json_path = args.value("json");
  const int world = mpi::size();
  const auto groups = parseRanks(args.value("ranks", ""), world);
  args.rejectUnknown();
  log::setLevel(log::Level::kWarning);
  const io::Scene scene = sim::makePileScene(pile);

  std::vector<Measurement> results;
  for (int ranks : groups) {
    MPI_Comm group;
    const int rank = mpi::rank();
    MPI_Comm_split(MPI_COMM_WORLD, rank < ranks ? 0 : MPI_UNDEFINED, rank, &group);
    Measurement m;
    if (group != MPI_COMM_NULL) {
      m = measure(scene, group, warmup, steps);
      MPI_Comm_free(&group);
    }
    MPI_Bcast(&m, sizeof m, MPI_BYTE, 0, MPI_COMM_WORLD);
    results.push_back(m);
  }
  if (mpi::rank() != 0) return 0;

  const double t1 = results.front().ranks == 1 ? results.front().seconds : 0.0;
  std::printf(
      "P-PILE strong scaling: %lld %s particles, kernel %s, %lld steps after %lld warm-up\n",
      static_cast<long long>(results.front().particles), pile.shapes.c_str(), pile.kernel.c_str(),
      static_cast<long long>(steps), static_cast<long long>(warmup));
  std::printf("%5s %9s %9s %14s %14s %10s %22s %8s %8s %8s\n", "ranks", "wall [s]", "contacts",
              "p-steps/s", "p-steps/s/core", "efficiency", "step ms min/mean/max", "broad%",
              "contact%", "comm%");
  nlohmann::json out = nlohmann::json::array();
  for (const auto& m : results) {
    const double rate = static_cast<double>(m.particles * m.steps) / m.seconds;
    const double eff = t1 > 0 ? t1 / (m.ranks * m.seconds) : 0.0;
    std::printf("%5d %9.3f %9lld %14.0f %14.0f %9.1f%% %6.2f/%6.2f/%6.2f %7.1f%% %7.1f%% %7.1f%%\n",
                m.ranks, m.seconds, static_cast<long long>(m.contacts), rate, rate / m.ranks,
                100 * eff, m.step_ms_min, m.step_ms_mean, m.step_ms_max, 100 * m.broadphase_share,
                100 * m.contact_share, 100 * m.comm_share);
    out.push_back({{"ranks", m.ranks},
                   {"particles", m.particles},
                   {"contacts", m.contacts},
                   {"steps", m.steps},
                   {"seconds", m.seconds},
                   {"particle_steps_per_second", rate},
                   {"particle_steps_per_second_per_core", rate / m.ranks},
                   {"parallel_efficiency", eff},
                   {"step_ms", {m.step_ms_min, m.step_ms_mean, m.step_ms_max}},
                   {"broadphase_share", m.broadphase_share},
                   {"contact_share", m.contact_share},
                   {"communication_share", m.comm_share}});
  }
  if (json_path) {
    std::ofstream(*json_path) << out.dump(2) << "\n";
    std::printf("written: %s\n", json_path->c_str());
  }
  return 0;
}

}  // namespace polydem::app
