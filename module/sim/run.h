// A complete run of a scene as `polydem run` does it: the simulation, its checks, series.csv,
// ParaView snapshots and summary.json in an output directory.
#pragma once

#include <mpi.h>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "comm/state_hash.h"
#include "io/scene.h"
#include "io/summary_json.h"

namespace polydem::sim {

struct RunOptions {
  std::string out_dir;                 // empty: no files at all (tests)
  std::optional<std::int64_t> steps;   // override the scene's step count
  std::optional<double> end_time;      // override the scene's end time
  std::optional<std::string> kernel;   // override the scene's kernel
  bool snapshots = true;               // write ParaView snapshots
  std::int64_t progress_every = 0;     // 0: the scene's, or automatic
};

struct RunResult {
  std::vector<io::CheckResult> checks;
  comm::StateHash hash;
  std::int64_t equilibrium_steps = 0;
  std::int64_t steps = 0;
  double time = 0.0;
  double wall_seconds = 0.0;
  bool all_checks_pass() const;
};

/// Applies the command-line overrides to a scene (steps / end time replace both of the scene's
/// stop settings; the kernel is checked against the registry).
void applyOverrides(io::Scene& scene, const RunOptions& options);

/// Runs `scene` on `comm` and writes its outputs (collective).
RunResult runScene(io::Scene scene, const RunOptions& options, MPI_Comm comm);

}  // namespace polydem::sim
