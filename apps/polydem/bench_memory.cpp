// polydem bench memory: the heap a P-PILE run (or a scene file's) holds, by structure, per particle
// and per contact,
// counted from what is allocated (Simulation::memoryUse, capacities times element sizes): the
// same figures on any machine for the same build and input. Figures at the end of the set-up
// (with the caller's own copy of the setup, which a scene reader or generator holds while the
// simulation is built) and the largest over the steps. Beside them, measured figures of this
// process (glibc's heap in use, peak resident memory), which vary with the machine and include
// the MPI library.
#include <malloc.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "commands.h"
#include "generators/pile_scene.h"
#include "polydem/core/error.h"
#include "polydem/core/logging.h"
#include "polydem/core/memory.h"
#include "polydem/core/mpi_env.h"
#include "polydem/geometry/shape_memory.h"
#include "polydem/scene/scene_reader.h"
#include "polydem/setup/setup.h"
#include "polydem/sim/simulation.h"

namespace polydem::app {

namespace {

// The caller's setup: its particle and shape lists.
std::uint64_t callerSetupBytes(const setup::Setup& scene) {
  std::uint64_t bytes = capacityBytes(scene.particles) + capacityBytes(scene.shapes);
  for (const auto& s : scene.shapes)
    bytes += capacityBytes(s.vertices) + capacityBytes(s.face_planes);
  return bytes;
}

// Sums over the ranks of `use`'s items.
std::vector<std::uint64_t> sumOverRanks(const sim::MemoryUse& use, MPI_Comm comm) {
  std::vector<std::uint64_t> mine, sum(use.size());
  for (const auto& item : use) mine.push_back(item.bytes);
  MPI_Allreduce(mine.data(), sum.data(), static_cast<int>(mine.size()), MPI_UINT64_T, MPI_SUM,
                comm);
  return sum;
}

// The rank's shape table by part (geometry/shape_memory.h), summed over the ranks, per particle.
void printShapeParts(const sim::Simulation& sim, double particles, MPI_Comm comm) {
  const auto parts = geometry::shapeMemory(sim.shapes());
  std::vector<std::uint64_t> mine, sum(2 * parts.size());
  for (const auto& p : parts) mine.insert(mine.end(), {p.bytes, p.blocks});
  MPI_Allreduce(mine.data(), sum.data(), static_cast<int>(mine.size()), MPI_UINT64_T, MPI_SUM,
                comm);
  if (mpi::rank() != 0) return;
  std::printf("shapes by part, at the end of the steps (%zu shapes on rank 0):\n",
              sim.shapes().size());
  std::printf("  %-12s %12s %10s %10s %10s  %s\n", "part", "bytes", "B/particle", "blocks",
              "blk/part.", "what");
  for (std::size_t i = 0; i < parts.size(); ++i) {
    std::printf("  %-12s %12llu %10.1f %10llu %10.2f  %s\n", parts[i].name.c_str(),
                static_cast<unsigned long long>(sum[2 * i]), sum[2 * i] / particles,
                static_cast<unsigned long long>(sum[2 * i + 1]), sum[2 * i + 1] / particles,
                parts[i].what.c_str());
  }
}

// Peak resident memory of this process (VmHWM), kB; 0 where /proc is not there.
long long peakResidentKb() {
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line)) {
    if (line.rfind("VmHWM:", 0) == 0) return std::stoll(line.substr(6));
  }
  return 0;
}

}  // namespace

int benchMemory(int argc, char** argv) {
  Args args(argc, argv, {"help", "records"});
  if (args.flag("help")) {
    std::printf(
        "usage: mpirun -n P polydem bench memory [--particles N] [--shapes cubes|mixed]\n"
        "         [--gap G] [--layers L] [--steps S] [--contact-model sub-contacts|point]\n"
        "         [--records] [--scene FILE] [--json FILE]\n"
        "  builds the P-PILE scene of bench scaling (--gap -0.001 with cubes: a dense pack, every\n"
        "  face in contact), runs S steps (default 20) and prints the heap it holds by structure,\n"
        "  per particle and per touching pair, summed over the ranks: counted from capacities\n"
        "  (the same on any machine), at the end of the set-up and the largest over the steps.\n"
        "  --records: keep the full contact records, as a run that writes snapshots, tracks\n"
        "  particles or checks contact forces does (without it, as a run without those).\n"
        "  --scene FILE: the scene file's run instead of the pile (its own contact model; the\n"
        "  pile's options do not apply), with its shape table by part.\n");
    return 0;
  }
  sim::PileOptions pile;
  pile.particles = args.integer("particles", 20000, 1);
  pile.shapes = args.value("shapes", "cubes");
  pile.layers = args.integer("layers", 10, 1);
  pile.gap = args.number("gap", -0.001);
  const std::string model = args.value("contact-model", "sub-contacts");
  if (const auto e = setup::unknownContactModel(model); !e.empty()) {
    throw UsageError("--contact-model: " + e);
  }
  const std::int64_t steps = args.integer("steps", 20, 0, Args::kInt64Max);
  const auto json_path = args.value("json");
  const auto scene_path = args.value("scene");
  const bool records = args.flag("records");
  args.rejectUnknown();
  log::setLevel(log::Level::kWarning);

  setup::Setup scene = scene_path ? scene::readScene(*scene_path) : sim::makePileScene(pile);
  if (!scene_path) scene.contact_model = model;
  const std::uint64_t caller = callerSetupBytes(scene);
  std::uint64_t caller_sum = 0;
  MPI_Allreduce(&caller, &caller_sum, 1, MPI_UINT64_T, MPI_SUM, MPI_COMM_WORLD);

  sim::Simulation sim(scene, MPI_COMM_WORLD);
  sim.keepContactRecords(records);
  const sim::MemoryUse names = sim.memoryUse();
  const auto setup_bytes = sumOverRanks(names, MPI_COMM_WORLD);
  std::vector<std::uint64_t> peak = setup_bytes;
  std::uint64_t peak_total = 0;
  sim::GlobalMonitors mon;
  for (std::int64_t s = 0; s < steps; ++s) {
    sim.step();
    const auto now = sumOverRanks(sim.memoryUse(), MPI_COMM_WORLD);
    for (std::size_t i = 0; i < now.size(); ++i) peak[i] = std::max(peak[i], now[i]);
    std::uint64_t total = 0;
    for (const auto b : now) total += b;
    peak_total = std::max(peak_total, total);
  }
  mon = sim.monitors();
  // The pairs and sub-contacts the history holds (a pair across a rank border on both ranks).
  std::int64_t counts[2] = {static_cast<std::int64_t>(sim.history().size()),
                            static_cast<std::int64_t>(sim.history().subCount())},
               sums[2] = {0, 0};
  MPI_Allreduce(counts, sums, 2, MPI_INT64_T, MPI_SUM, MPI_COMM_WORLD);
  printShapeParts(sim, static_cast<double>(mon.particles), MPI_COMM_WORLD);
  const struct mallinfo2 heap = mallinfo2();
  long long rss_kb = peakResidentKb(), rss_sum = 0;
  double heap_mine = static_cast<double>(heap.uordblks + heap.hblkhd), heap_sum = 0;
  MPI_Reduce(&rss_kb, &rss_sum, 1, MPI_LONG_LONG, MPI_SUM, 0, MPI_COMM_WORLD);
  MPI_Reduce(&heap_mine, &heap_sum, 1, MPI_DOUBLE, MPI_SUM, 0, MPI_COMM_WORLD);
  if (mpi::rank() != 0) return 0;

  const double n = static_cast<double>(mon.particles);
  const double contacts = static_cast<double>(std::max<std::int64_t>(1, mon.contacts));
  std::uint64_t setup_total = caller_sum;
  for (const auto b : setup_bytes) setup_total += b;
  std::printf(
      "%s memory: %lld %s, gap %g, contact model %s, %d rank(s), %lld steps: %lld touching "
      "pairs (%.2f per particle); the history holds %lld pairs and %lld sub-contacts; full "
      "contact records %s\n",
      scene_path ? scene_path->c_str() : "P-PILE", static_cast<long long>(mon.particles),
      scene_path ? "particles" : pile.shapes.c_str(), scene_path ? 0.0 : pile.gap,
      sim.scene().contact_model.c_str(), mpi::size(), static_cast<long long>(steps),
      static_cast<long long>(mon.contacts), mon.contacts / n, static_cast<long long>(sums[0]),
      static_cast<long long>(sums[1]), records ? "kept (--records)" : "not kept");
  std::printf("%-14s %12s %12s %10s %10s  %s\n", "structure", "set-up [B]", "steps [B]",
              "B/particle", "B/contact", "what");
  nlohmann::json structures = nlohmann::json::object();
  for (std::size_t i = 0; i < names.size(); ++i) {
    std::printf("%-14s %12llu %12llu %10.1f %10.1f  %s\n", names[i].name.c_str(),
                static_cast<unsigned long long>(setup_bytes[i]),
                static_cast<unsigned long long>(peak[i]), peak[i] / n, peak[i] / contacts,
                names[i].what.c_str());
    structures[names[i].name] = {{"setup_bytes", setup_bytes[i]}, {"peak_bytes", peak[i]}};
  }
  std::printf("%-14s %12llu %12s %10s %10s  %s\n", "caller_setup",
              static_cast<unsigned long long>(caller_sum), "-", "-", "-",
              "the generator's setup, alive while the simulation is built");
  peak_total = std::max(peak_total, setup_total - caller_sum);
  std::printf("%-14s %12llu %12llu %10.1f %10.1f\n", "total",
              static_cast<unsigned long long>(setup_total),
              static_cast<unsigned long long>(peak_total), peak_total / n, peak_total / contacts);
  std::printf(
      "(counted: capacities times element sizes, summed over the ranks; set-up: after the\n"
      " simulation is built, the caller's setup included; steps: the largest over the steps,\n"
      " per structure and in total. Measured here, machine- and library-dependent: heap in use\n"
      " %s (glibc, all allocations, MPI's included), peak resident %s, summed over the ranks)\n",
      formatBytes(heap_sum).c_str(), formatBytes(1024.0 * rss_sum).c_str());
  if (json_path) {
    nlohmann::json out = {{"particles", mon.particles},
                          {"contacts", mon.contacts},
                          {"history_pairs", sums[0]},
                          {"subcontacts", sums[1]},
                          {"ranks", mpi::size()},
                          {"steps", steps},
                          {"records_kept", records},
                          {"structures", structures},
                          {"caller_setup_bytes", caller_sum},
                          {"setup_bytes", setup_total},
                          {"peak_bytes", peak_total},
                          {"measured_heap_bytes", heap_sum},
                          {"measured_peak_rss_bytes", 1024.0 * rss_sum}};
    std::ofstream(*json_path) << out.dump(2) << "\n";
    std::printf("written: %s\n", json_path->c_str());
  }
  return 0;
}

}  // namespace polydem::app
