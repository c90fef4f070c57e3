// Checkpoints of a run as `polydem run` takes them: on a schedule (every N steps, every T seconds
// of wall clock) and when the process is asked to stop (SIGTERM, SIGUSR1), into
// <out>/checkpoints/checkpoint_<step>_<run id>.h5, keeping the newest K of this run's (the run id
// is new for every run, a continued one too). See docs/checkpoint.md.
#pragma once

#include <mpi.h>

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "polydem/checkpoint/checkpoint.h"
#include "polydem/run/checks.h"
#include "polydem/run/tracker.h"
#include "polydem/setup/setup.h"
#include "polydem/sim/simulation.h"

namespace polydem::run {

/// Makes SIGTERM and SIGUSR1 set a flag (async-signal-safe) instead of ending the process.
/// `polydem run` calls it first thing, before MPI starts and before any file is read, so that a
/// signal at any moment of the start-up is kept for the first step's check. Idempotent.
/// `interrupt`: SIGINT (Ctrl-C) too, as `polydem fos` takes it.
void installStopSignals(bool interrupt = false);
/// The signal number received since installStopSignals() on this process, or 0.
int stopSignalReceived();
/// The signal some rank of `comm` has received (the largest number), or 0 (collective).
int stopSignalOnAnyRank(MPI_Comm comm);
/// "SIGTERM", "SIGUSR1", "SIGINT" or "signal N".
std::string signalName(int signal);

/// The run state a checkpoint stores besides the simulation (sim::CheckpointData::run_state):
/// the tracker's initial states and every check's accumulated values, bit for bit, and the
/// kernel and contact model the run used, which a command line may have set over the stored
/// scene's (JSON).
std::string runStateJson(const setup::Setup& scene, const Tracker& tracker,
                         const std::vector<std::unique_ptr<Check>>& checks);
/// Sets the kernel and contact model `json` stores on the scene a run continues with; a file
/// that stores none (written before they were stored) leaves the scene's. Throws CheckpointError
/// naming `file` for an unknown kernel or model.
void restoreRunSettings(const std::string& json, const std::string& file, setup::Setup& scene);
/// What a continued run changes on the scene it was given (the stored one or a replacement):
/// the stored run settings (restoreRunSettings), and for a version 1 file, written before
/// sub-contacts existed, the single-point model it was written with (docs/checkpoint.md). Logs
/// what an older file lacks. `polydem run --restart` and Python's Simulation.restart both use it.
void prepareContinuation(const sim::CheckpointData& data, const std::string& file,
                         setup::Setup& scene);
/// Puts them back; throws CheckpointError naming `file` if they do not fit the scene's checks.
void restoreRunState(const std::string& json, const std::string& file, Tracker& tracker,
                     std::vector<std::unique_ptr<Check>>& checks);

class CheckpointSchedule {
 public:
  /// `scene_toml`: the scene text the checkpoints store. `dir`: where they go (empty: nowhere,
  /// but a stop signal still stops the run). Collective: rank 0 draws the run id.
  CheckpointSchedule(const setup::CheckpointSpec& spec, std::filesystem::path dir,
                     std::string scene_toml, std::string scene_file, std::string code_version,
                     const Tracker& tracker, const std::vector<std::unique_ptr<Check>>& checks,
                     MPI_Comm comm);

  /// The simulation's step hook (collective, once per step): writes a checkpoint when one is
  /// due, and returns true when some rank received a stop signal (one allreduce decides both,
  /// with rank 0's wall clock).
  bool afterStep(sim::Simulation& sim);
  /// Writes a checkpoint of the current state and prunes old ones (collective); its path.
  std::filesystem::path write(sim::Simulation& sim);
  /// After the run: whether some rank received a stop signal since the last step's check
  /// (collective). If so, stopSignal() is that signal from now on.
  bool signalAfterRun();

  /// The id in the names of this run's checkpoints (empty without a directory).
  const std::string& runId() const { return run_id_; }
  /// The signal that stopped the run (0: none).
  int stopSignal() const { return stop_signal_; }
  const std::filesystem::path& lastWritten() const { return last_; }

 private:
  void drawRunId();  // collective

  setup::CheckpointSpec spec_;
  std::filesystem::path dir_;
  std::string scene_toml_, scene_file_, code_version_, run_id_;
  const Tracker& tracker_;
  const std::vector<std::unique_ptr<Check>>& checks_;
  MPI_Comm comm_;
  int stop_signal_ = 0;
  std::chrono::steady_clock::time_point last_wall_ = std::chrono::steady_clock::now();
  std::filesystem::path last_;
};

}  // namespace polydem::run
