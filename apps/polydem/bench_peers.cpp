// polydem bench peers: the settled pile of bench yade and bench lammps (bench_pile.h) settled
// once and run from the same state in polydem (each kernel and contact model), in Yade's
// Polyhedra and in LAMMPS's BODY package, side by side: particle-steps per second of one core,
// contacts, the peak resident memory of each code's process and each code's own count of what it
// holds. A peer that is not installed gets a row that says so. The models and how their
// parameters are matched: bench_yade.cpp, bench_lammps.cpp. scripts/peer_table.py puts these
// figures beside the dense pack's in one table of docs/performance.md.
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "bench_pile.h"
#include "commands.h"
#include "polydem/core/logging.h"
#include "polydem/core/mpi_env.h"

namespace polydem::app {

namespace {

// One row of the table: a code's result, or the reason it has none.
struct PeerRow {
  std::string code;
  std::string status;  // "ok", "not installed", "no result"
  PileResult result;
};

// The peer's row: run in a directory of its own (kept under `keep` when given).
PeerRow peerRow(const std::string& code, const std::string& exe, const setup::Setup& scene,
                const PileBenchOptions& o) {
  PeerRow row{code, "not installed", {}};
  if (exe.empty()) return row;
  const bool temporary = o.keep.empty();  // then a new directory of our own, safe to remove
  const std::filesystem::path dir =
      std::filesystem::absolute(temporary ? benchDirectory("", "polydem-bench-" + code)
                                          : benchDirectory(o.keep + "/" + code, ""));
  const auto r = code == "yade" ? runYade(scene, o, exe, dir) : runLammps(scene, o, exe, dir);
  if (temporary) std::filesystem::remove_all(dir);
  row.status = r ? "ok" : "no result";
  if (r) row.result = *r;
  return row;
}

// The rate of `code`'s row; 0 where it has none.
double rateOf(const std::vector<PeerRow>& rows, const std::string& code) {
  for (const auto& row : rows) {
    if (row.code == code && row.status == "ok") return row.result.particle_steps_per_second;
  }
  return 0.0;
}

void printRows(const std::vector<PeerRow>& rows) {
  const double yade = rateOf(rows, "yade"), lammps = rateOf(rows, "lammps");
  std::printf("%-8s %-24s %-17s %9s %13s %7s %9s %9s %8s %12s\n", "code", "kernel", "model",
              "particles", "particle-st/s", "x Yade", "x LAMMPS", "contacts", "peak MB",
              "counted B/p");
  for (const auto& row : rows) {
    if (row.status != "ok") {
      std::printf("%-8s %s\n", row.code.c_str(), row.status.c_str());
      continue;
    }
    const PileResult& r = row.result;
    char x_yade[32] = "-", x_lammps[32] = "-", contacts[32] = "-", counted[32] = "-";
    if (yade > 0) std::snprintf(x_yade, sizeof x_yade, "%.1f", r.particle_steps_per_second / yade);
    if (lammps > 0) {
      std::snprintf(x_lammps, sizeof x_lammps, "%.1f", r.particle_steps_per_second / lammps);
    }
    if (r.contacts >= 0) std::snprintf(contacts, sizeof contacts, "%lld", (long long)r.contacts);
    if (r.counted_bytes > 0) {
      std::snprintf(counted, sizeof counted, "%.0f",
                    r.counted_bytes / static_cast<double>(r.particles));
    }
    std::printf("%-8s %-24s %-17s %9lld %13.0f %7s %9s %9s %8.1f %12s\n", r.code.c_str(),
                r.kernel.c_str(), r.model.c_str(), static_cast<long long>(r.particles),
                r.particle_steps_per_second, x_yade, x_lammps, contacts,
                static_cast<double>(r.peak_kb) / 1024.0, counted);
  }
  std::printf(
      "(peak MB: each code's process; polydem's also settled the pile and ran the rows above it.\n"
      " counted B/p: polydem's heap by its structures (bench memory's count), LAMMPS's own\n"
      " \"Per MPI rank memory allocation\", per particle)\n");
}

nlohmann::json toJson(const std::vector<PeerRow>& rows, const PileBenchOptions& o,
                      std::int64_t settle_steps, bool reached) {
  nlohmann::json out = {{"pile",
                         {{"particles", o.particles},
                          {"layers", o.layers},
                          {"settle_steps", settle_steps},
                          {"settle_limit", o.settle},
                          {"settled", reached},
                          {"steps", o.steps},
                          {"warmup", o.warmup}}},
                        {"rows", nlohmann::json::array()}};
  for (const auto& row : rows) {
    const PileResult& r = row.result;
    nlohmann::json j = {{"code", row.code}, {"status", row.status}};
    if (row.status == "ok") {
      j.update({{"kernel", r.kernel},
                {"contact_model", r.model},
                {"particles", r.particles},
                {"steps", r.steps},
                {"seconds", r.seconds},
                {"particle_steps_per_second", r.particle_steps_per_second},
                {"contacts", r.contacts},
                {"peak_kb", r.peak_kb},
                {"counted_bytes", r.counted_bytes}});
      if (!r.structures.empty()) {
        j["structures"] = nlohmann::json::object();
        for (const auto& [name, bytes] : r.structures) j["structures"][name] = bytes;
      }
    }
    out["rows"].push_back(j);
  }
  return out;
}

}  // namespace

int benchPeers(int argc, char** argv) {
  Args args(argc, argv, {"help"});
  if (args.flag("help")) {
    std::printf(
        "usage: polydem bench peers [--particles N] [--layers L] [--settle S] [--steps M]\n"
        "                           [--warmup W] [--kernels a,b] [--contact-models m,n]\n"
        "                           [--yade PATH] [--lmp PATH] [--keep DIR] [--json FILE]\n"
        "  the settled pile of bench yade and bench lammps (N randomly turned unit cubes, default\n"
        "  1000, settled by polydem in at most S steps, default 150000) settled once, then M\n"
        "  steps (default 100, after W = 10 untimed) from that state in polydem (each kernel and\n"
        "  contact model), Yade and LAMMPS (each where installed; --yade, --lmp: the\n"
        "  executables): particle-steps per second of one core, contacts, each process's peak\n"
        "  resident memory and each code's own count of what it holds. --keep DIR: the peers'\n"
        "  input and output in DIR/yade and DIR/lammps.\n");
    return 0;
  }
  const PileBenchOptions o = parsePileOptions(args, "yade");
  const std::string lmp = args.value("lmp", "");
  const auto json_path = args.value("json");
  args.rejectUnknown();
  if (mpi::rank() != 0) return 0;  // one core: rank 0 measures
  log::setLevel(log::Level::kWarning);

  std::int64_t settle_steps = 0;
  bool reached = false;
  const setup::Setup scene = settledPile(o, settle_steps, reached);
  std::printf(
      "P-PEERS: %lld randomly turned unit cubes in a box, settled by polydem in %lld steps (force "
      "ratio %s 1e-3); then %lld steps (after %lld untimed) from that state in each code\n\n",
      static_cast<long long>(o.particles), static_cast<long long>(settle_steps),
      reached ? "reached" : "NOT reached", static_cast<long long>(o.steps),
      static_cast<long long>(o.warmup));

  std::vector<PeerRow> rows;
  for (const auto& kernel : o.kernels) {
    for (const auto& model : o.models) {
      rows.push_back({"polydem", "ok", runPolydemPile(scene, kernel, model, o)});
    }
  }
  rows.push_back(peerRow("yade", findExecutable("yade", o.peer), scene, o));
  rows.push_back(peerRow("lammps", findExecutable("lmp", lmp), scene, o));
  printRows(rows);
  if (json_path) {
    std::ofstream(*json_path) << toJson(rows, o, settle_steps, reached).dump(2) << "\n";
    std::printf("written: %s\n", json_path->c_str());
  }
  return 0;
}

}  // namespace polydem::app
