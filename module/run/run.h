// A complete run of a scene as `polydem run` does it: the simulation, its checks, series.csv,
// ParaView snapshots and summary.json in an output directory.
#pragma once

#include <mpi.h>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "polydem/comm/state_hash.h"
#include "polydem/output/summary_json.h"
#include "polydem/setup/setup.h"

namespace polydem::run {

struct RunOptions {
  std::string out_dir;                       // empty: no files at all (tests)
  std::optional<std::int64_t> steps;         // override the scene's step count
  std::optional<double> end_time;            // override the scene's end time
  std::optional<std::string> kernel;         // override the scene's kernel
  std::optional<std::string> contact_model;  // override the scene's contact model
  bool snapshots = true;                     // write ParaView snapshots
  std::int64_t progress_every = 0;           // 0: the scene's, or automatic
  // --- checkpoints (docs/checkpoint.md) -----------------------------------------------------
  std::string scene_text;                        // the scene file's text, stored in checkpoints
  std::optional<std::int64_t> checkpoint_every;  // override [checkpoint] every_steps
  std::optional<double> checkpoint_seconds;      // override [checkpoint] every_seconds
  std::optional<int> checkpoint_keep;            // override [checkpoint] keep
  bool stop_on_signals = false;     // SIGTERM/SIGUSR1: checkpoint at the end of the step and stop
  std::string code_version;         // stored in checkpoints
  std::string program = "polydem";  // the executable, for the restart command printed
};

struct RunResult {
  std::vector<output::CheckResult> checks;
  comm::StateHash hash;
  std::int64_t equilibrium_steps = 0;
  std::int64_t steps = 0;
  double time = 0.0;
  double wall_seconds = 0.0;
  std::string stop_signal;  // "SIGTERM" or "SIGUSR1" if a signal came during the run, else empty
  bool signal_after_end = false;  // it came after the last step: the run was complete anyway
  std::string checkpoint;         // the checkpoint written because of the signal, if any
  bool all_checks_pass() const;
  /// A signal stopped the run before its end (its checks then judge a part of the run).
  bool stopped_early() const { return !stop_signal.empty() && !signal_after_end; }
};

/// Applies the command-line overrides to a scene (steps / end time replace both of the scene's
/// stop settings; the kernel is checked against the registry).
void applyOverrides(setup::Setup& scene, const RunOptions& options);

/// Runs `scene` on `comm` and writes its outputs (collective).
RunResult runScene(setup::Setup scene, const RunOptions& options, MPI_Comm comm);

/// Continues the run of the checkpoint `file` on `comm` (any rank count) and writes the outputs
/// of the continued part (collective). The scene is the stored one, or `scene_file` if given,
/// which must describe the same run up to its stop, [output] and [checkpoint] settings
/// (scene::sceneDifference); the overrides of `options` apply as to a new run. Throws
/// CheckpointError (on every rank) for a bad or mismatching checkpoint.
RunResult continueRun(const std::string& file, const std::optional<std::string>& scene_file,
                      RunOptions options, MPI_Comm comm);

}  // namespace polydem::run
