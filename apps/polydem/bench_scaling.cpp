// polydem bench scaling: strong or weak scaling of a P-PILE scene. The same run measures the scene
// on 1 rank and on larger groups of the launched ranks (the others wait), so every figure has its
// 1-rank peer from the same machine and the same moment. --control adds the hardware's own
// limit: the 1-rank run on every launched rank at once, side by side, as independent runs.
// Beside the times it reports the deterministic balance figures of every group (owned
// particles, ghosts, pairs, contacts, bytes and messages per rank: sim/balance_figures.h).
#include <chrono>
#include <cstdio>
#include <ctime>
#include <fstream>
#include <nlohmann/json.hpp>

#include "commands.h"
#include "generators/pile_scene.h"
#include "polydem/core/error.h"
#include "polydem/core/logging.h"
#include "polydem/core/mpi_env.h"
#include "polydem/core/strings.h"
#include "polydem/setup/setup.h"
#include "polydem/sim/balance_figures.h"
#include "polydem/sim/simulation.h"

namespace polydem::app {

namespace {

struct ScalingRun {
  int ranks = 0;
  bool control = false;      // independent 1-rank runs side by side, one per launched rank
  double seconds = 0.0;      // timed steps only (control: the mean over the runs)
  double cpu_seconds = 0.0;  // CPU time of the timed steps, the busiest rank's main thread
  std::int64_t steps = 0, particles = 0, contacts = 0;
  double step_ms_min = 0, step_ms_mean = 0, step_ms_max = 0;  // per-rank loop time per step
  double broadphase_share = 0.0, contact_share = 0.0, comm_share = 0.0;
  sim::BalanceFigures balance;
};

// --ranks r1,r2,... (each in 1..world), or 1, 2, 4, ... and the world.
std::vector<int> parseRanks(Args& args, int world) {
  std::vector<int> out;
  if (args.value("ranks")) {
    for (const long long r : args.integers("ranks", "", 1, world))
      out.push_back(static_cast<int>(r));
    return out;
  }
  for (int r = 1; r < world; r *= 2) out.push_back(r);
  out.push_back(world);
  return out;
}

// CPU time of the calling thread: on a loaded machine the figure that wall time is not.
double threadCpuSeconds() {
  timespec ts;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

ScalingRun measure(const setup::Setup& scene, MPI_Comm comm, std::int64_t warmup,
                   std::int64_t steps) {
  sim::Simulation sim(scene, comm);
  sim.keepContactRecords(false);  // nothing here reads them (a run without snapshots)
  for (std::int64_t i = 0; i < warmup; ++i) sim.step();
  sim.loop().timing().clear();
  MPI_Barrier(comm);
  const auto t0 = std::chrono::steady_clock::now();
  const double cpu0 = threadCpuSeconds();
  for (std::int64_t i = 0; i < steps; ++i) sim.step();
  const double cpu = threadCpuSeconds() - cpu0;
  MPI_Barrier(comm);
  const auto t1 = std::chrono::steady_clock::now();
  ScalingRun m;
  m.cpu_seconds = mpi::allreduceMax(cpu, comm);
  m.ranks = mpi::size(comm);
  m.seconds = std::chrono::duration<double>(t1 - t0).count();
  m.steps = steps;
  const auto mon = sim.monitors();
  m.particles = mon.particles;
  m.contacts = mon.contacts;
  // Per-rank loop time per step: the sum of the rank's timers.
  double mine = 0.0;
  for (const auto& e : sim.loop().timing().entries()) mine += e.seconds;
  const double per_step = 1e3 * mine / static_cast<double>(std::max<std::int64_t>(1, steps));
  m.step_ms_min = mpi::allreduceMin(per_step, comm);
  m.step_ms_max = mpi::allreduceMax(per_step, comm);
  double sum = 0.0;
  MPI_Allreduce(&per_step, &sum, 1, MPI_DOUBLE, MPI_SUM, comm);
  m.step_ms_mean = sum / m.ranks;
  for (const auto& r : sim.loop().timing().reduce(comm)) {
    if (r.name == "broadphase") m.broadphase_share = r.share;
    if (r.name == "contacts") m.contact_share = r.share;
    // The exchange's operators (sim/step/step_list.cpp); the early contacts are contact work.
    for (const char* name : {"domain check", "balance", "exchange", "exchange finish"}) {
      if (r.name == name) m.comm_share += r.share;
    }
  }
  m.balance = sim::balanceFigures(sim);
  return m;
}

/// The 1-rank scene on every launched rank at once; the mean time of those runs.
ScalingRun measureControl(const setup::Setup& scene, std::int64_t warmup, std::int64_t steps) {
  MPI_Barrier(MPI_COMM_WORLD);
  ScalingRun m = measure(scene, MPI_COMM_SELF, warmup, steps);
  double sum = 0.0;
  MPI_Allreduce(&m.seconds, &sum, 1, MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
  m.seconds = sum / mpi::size();
  m.ranks = mpi::size();
  m.control = true;
  return m;
}

nlohmann::json row(const ScalingRun& m, double rate, double eff, double hw_eff) {
  nlohmann::json j = {{"ranks", m.ranks},
                      {"particles", m.particles},
                      {"contacts", m.contacts},
                      {"steps", m.steps},
                      {"seconds", m.seconds},
                      {"cpu_seconds", m.cpu_seconds},
                      {"particle_steps_per_second", rate},
                      {"particle_steps_per_second_per_core", rate / m.ranks},
                      {"parallel_efficiency", eff},
                      {"step_ms", {m.step_ms_min, m.step_ms_mean, m.step_ms_max}},
                      {"broadphase_share", m.broadphase_share},
                      {"contact_share", m.contact_share},
                      {"communication_share", m.comm_share}};
  if (m.control) {
    j["control"] = "independent 1-rank runs side by side, one per rank";
  } else {
    if (hw_eff > 0) j["efficiency_of_hardware_control"] = hw_eff;
    const auto figures = sim::toJson(m.balance);
    j["balance"] = figures["balance"];
    j["communication_seconds_per_step"] = figures["communication_seconds_per_step"];
  }
  return j;
}

std::string percent(double x) {
  char text[32];
  std::snprintf(text, sizeof text, "%.1f%%", 100 * x);
  return text;
}

void printBalance(const std::vector<ScalingRun>& results) {
  std::printf(
      "\nbalance after the last step, per rank max/mean (counts: the same on any machine):\n"
      "%5s %13s %7s %7s %10s %7s %8s %7s %8s %11s %9s %7s %26s %7s %8s\n",
      "ranks", "blocks", "owned", "ghosts", "cand.pairs", "pairs", "contacts", "work", "work eff",
      "bytes/step", "msgs/step", "ghosts", "exchange ms wait/xfer/other", "early", "early ms");
  for (const auto& m : results) {
    if (m.control) continue;
    const auto& b = m.balance;
    std::printf(
        "%5d %4dx%3dx%3d %7.3f %7.3f %10.3f %7.3f %8.3f %7.3f %7.1f%% %11.0f %9.2f %7.0f "
        "%8.3f/%7.3f/%7.3f %6.1f%% %8.3f\n",
        m.ranks, b.blocks[0], b.blocks[1], b.blocks[2], b.owned.ratio(), b.ghosts.ratio(),
        b.candidate_pairs.ratio(), b.evaluated_pairs.ratio(), b.contacts.ratio(), b.work.ratio(),
        100 * sim::modelledEfficiency(b), b.bytes_per_step.mean, b.messages_per_step.mean,
        b.ghosts.mean, 1e3 * b.wait_seconds.mean, 1e3 * b.transfer_seconds.mean,
        1e3 * b.bookkeeping_seconds.mean,
        b.evaluated_pairs.mean > 0 ? 100 * b.early_pairs.mean / b.evaluated_pairs.mean : 0.0,
        1e3 * b.early_seconds.mean);
  }
  std::printf(
      "(pairs: kernel calls, a pair across a rank border on both ranks; work: the load model;\n"
      " work eff: the work done once / (ranks x the busiest rank's work), the efficiency that the\n"
      " balance and the duplicated border pairs allow; bytes, messages: mean per rank and step,\n"
      " one message per neighbour rank (empty ones included), a ghost kept from the step before\n"
      " as a 104-byte state update, a new one whole (134 bytes); ghosts: mean per rank;\n"
      " exchange times: mean per rank and step, not deterministic; wait: until the neighbours'\n"
      " messages arrived; early: the share of the pairs evaluated while the exchange before the\n"
      " step was in flight, and the time that took, mean per rank and step)\n");
}

}  // namespace

int benchScaling(int argc, char** argv) {
  Args args(argc, argv, {"help", "control", "overlap"});
  if (args.flag("help")) {
    std::printf(
        "usage: mpirun -n P polydem bench scaling [--particles N | --per-rank N]\n"
        "         [--shapes mixed|cubes] [--layers L] [--steps S] [--warmup W] [--kernel NAME]\n"
        "         [--ranks 1,2,...] [--control] [--contact-model sub-contacts|point]\n"
        "         [--json FILE] [--overlap]\n"
        "         [--gap G]   lattice gap relative to the size (default 0.05: particles start\n"
        "                     apart and fall; -0.001 with cubes: a dense pack, every face in\n"
        "                     contact from the first step)\n"
        "         [--floor-width F]  no walls, a floor F times as wide as the pile and the\n"
        "                     default [domain] box (default: walls around the pile)\n"
        "  runs the P-PILE scene on 1 rank and on groups of the P launched ranks (default 1, 2,\n"
        "  4, ..., P) and prints particle-steps per second per core, parallel efficiency and the\n"
        "  balance figures per rank. --per-rank N: weak scaling, N particles per rank of each\n"
        "  group. --control: also the 1-rank run on all P ranks at once (independent runs side\n"
        "  by side): the efficiency the hardware itself allows. --overlap: [domain]\n"
        "  overlap_exchange = true (local pairs evaluated while the exchange is in flight).\n");
    return 0;
  }
  sim::PileOptions pile;
  const std::int64_t per_rank = args.integer("per-rank", 0, 1);
  pile.particles = args.integer("particles", 20000, 1);
  pile.shapes = args.value("shapes", "mixed");
  pile.kernel = args.value("kernel", "gjk-epa-ipm");
  const std::string model = args.value("contact-model", "sub-contacts");
  if (const auto e = setup::unknownContactModel(model); !e.empty()) {
    throw UsageError("--contact-model: " + e);
  }
  pile.layers = args.integer("layers", 10, 1);
  pile.gap = args.number("gap", pile.gap);
  pile.floor_width = args.number("floor-width", 0.0, 0.0);
  const std::int64_t steps = args.integer("steps", 100, 1, Args::kInt64Max);
  const std::int64_t warmup = args.integer("warmup", 20, 0, Args::kInt64Max);
  const bool control = args.flag("control");
  const bool overlap = args.flag("overlap");
  const auto json_path = args.value("json");
  const int world = mpi::size();
  const auto groups = parseRanks(args, world);
  args.rejectUnknown();
  log::setLevel(log::Level::kWarning);
  auto sceneFor = [&](int ranks) {
    sim::PileOptions o = pile;
    if (per_rank > 0) o.particles = per_rank * ranks;
    setup::Setup scene = sim::makePileScene(o);
    scene.contact_model = model;
    scene.domain.overlap_exchange = overlap;
    return scene;
  };

  std::vector<ScalingRun> results;
  for (int ranks : groups) {
    MPI_Comm group;
    const int rank = mpi::rank();
    MPI_Comm_split(MPI_COMM_WORLD, rank < ranks ? 0 : MPI_UNDEFINED, rank, &group);
    ScalingRun m;
    if (group != MPI_COMM_NULL) {
      m = measure(sceneFor(ranks), group, warmup, steps);
      MPI_Comm_free(&group);
    }
    MPI_Bcast(&m, sizeof m, MPI_BYTE, 0, MPI_COMM_WORLD);
    results.push_back(m);
  }
  if (control) results.push_back(measureControl(sceneFor(1), warmup, steps));
  if (mpi::rank() != 0) return 0;

  const ScalingRun& lone = results.front();
  const double t1 = lone.ranks == 1 ? lone.seconds : 0.0;
  double control_ratio = 0.0;  // lone 1-rank time / side-by-side 1-rank time
  if (control && t1 > 0) control_ratio = t1 / results.back().seconds;
  std::printf(
      "P-PILE %s scaling: %s %s particles%s, kernel %s, contact model %s, %lld steps after %lld "
      "warm-up, exchange overlap %s\n",
      per_rank > 0 ? "weak" : "strong",
      per_rank > 0 ? cat(per_rank, " per rank").c_str() : cat(results.front().particles).c_str(),
      pile.shapes.c_str(),
      pile.floor_width > 0 ? cat(" on a floor ", pile.floor_width, "x as wide").c_str() : "",
      pile.kernel.c_str(), model.c_str(), static_cast<long long>(steps),
      static_cast<long long>(warmup), overlap ? "on" : "off");
  std::printf("%7s %9s %9s %14s %14s %10s %9s %22s %8s %8s %8s\n", "ranks", "wall [s]", "contacts",
              "p-steps/s", "p-steps/s/core", "efficiency", "of hw", "step ms min/mean/max",
              "broad%", "contact%", "comm%");
  nlohmann::json out = nlohmann::json::array();
  for (const auto& m : results) {
    const double rate = static_cast<double>(m.particles * m.steps) / m.seconds;
    // Strong: t1 / (P tP); weak (P times the particles): t1 / tP. Control: t1 / t(side by side).
    double eff = 0.0;
    if (t1 > 0) eff = m.control || per_rank > 0 ? t1 / m.seconds : t1 / (m.ranks * m.seconds);
    const double hw_eff =
        !m.control && control_ratio > 0 && m.ranks == world ? eff / control_ratio : 0;
    std::printf(
        "%7s %9.3f %9lld %14.0f %14.0f %9.1f%% %8s %6.2f/%6.2f/%6.2f %7.1f%% %7.1f%% "
        "%7.1f%%\n",
        m.control ? cat(m.ranks, "x1").c_str() : cat(m.ranks).c_str(), m.seconds,
        static_cast<long long>(m.contacts), m.control ? rate * m.ranks : rate,
        m.control ? rate : rate / m.ranks, 100 * eff, hw_eff > 0 ? percent(hw_eff).c_str() : "",
        m.step_ms_min, m.step_ms_mean, m.step_ms_max, 100 * m.broadphase_share,
        100 * m.contact_share, 100 * m.comm_share);
    out.push_back(row(m, m.control ? rate * m.ranks : rate, eff, hw_eff));
  }
  if (control) {
    std::printf(
        "(%dx1: the 1-rank run on all %d ranks at once; its efficiency is what the hardware "
        "allows, 'of hw' divides by it)\n",
        world, world);
  }
  printBalance(results);
  if (json_path) {
    std::ofstream(*json_path) << out.dump(2) << "\n";
    std::printf("written: %s\n", json_path->c_str());
  }
  return 0;
}

}  // namespace polydem::app
