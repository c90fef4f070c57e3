#include "polydem/run/run_checkpoint.h"

#include <csignal>
#include <cstring>
#include <nlohmann/json.hpp>

#include "polydem/checkpoint/checkpoint.h"
#include "polydem/contact/contact.h"
#include "polydem/core/error.h"
#include "polydem/core/interrupt.h"
#include "polydem/core/logging.h"
#include "polydem/core/mpi_env.h"
#include "polydem/core/strings.h"
#include "polydem/core/timing_pool.h"

namespace polydem::run {

namespace {

volatile std::sig_atomic_t g_stop_signal = 0;

extern "C" void onStopSignal(int signal) {
  g_stop_signal = signal;
}

// Doubles as their bit patterns: exact, and NaN survives (JSON has no NaN).
std::vector<std::uint64_t> toBits(const std::vector<double>& values) {
  std::vector<std::uint64_t> bits(values.size());
  std::memcpy(bits.data(), values.data(), values.size() * sizeof(double));
  return bits;
}

std::vector<double> fromBits(const std::vector<std::uint64_t>& bits) {
  std::vector<double> values(bits.size());
  std::memcpy(values.data(), bits.data(), bits.size() * sizeof(double));
  return values;
}

// Checkpoints are numbered by the steps of both stages, so that names sort in run order.
std::int64_t runSteps(const sim::Simulation& sim) {
  return sim.stage() == sim::Stage::kEquilibrium ? sim.stepCount()
                                                 : sim.equilibriumSteps() + sim.stepCount();
}

}  // namespace

void installStopSignals(bool interrupt) {
  struct sigaction action {};
  action.sa_handler = onStopSignal;
  sigemptyset(&action.sa_mask);
  action.sa_flags = SA_RESTART;
  sigaction(SIGTERM, &action, nullptr);
  sigaction(SIGUSR1, &action, nullptr);
  if (interrupt) sigaction(SIGINT, &action, nullptr);
  setInterruptProbe(&stopSignalReceived);  // long set-up work (a rock mass cut) stops too
}

int stopSignalReceived() {
  return g_stop_signal;
}

int stopSignalOnAnyRank(MPI_Comm comm) {
  int local = stopSignalReceived(), global = 0;
  MPI_Allreduce(&local, &global, 1, MPI_INT, MPI_MAX, comm);
  return global;
}

std::string signalName(int signal) {
  if (signal == SIGTERM) return "SIGTERM";
  if (signal == SIGUSR1) return "SIGUSR1";
  if (signal == SIGINT) return "SIGINT";
  return cat("signal ", signal);
}

std::string runStateJson(const setup::Setup& scene, const Tracker& tracker,
                         const std::vector<std::unique_ptr<Check>>& checks) {
  nlohmann::json j;
  j["kernel"] = scene.kernel;
  j["contact_model"] = scene.contact_model;
  j["tracker_initial_bits"] = toBits(tracker.initialState());
  nlohmann::json c = nlohmann::json::object();
  for (const auto& check : checks) c[check->spec().name] = toBits(check->state());
  j["checks_bits"] = c;
  return j.dump();
}

void restoreRunSettings(const std::string& json, const std::string& file, setup::Setup& scene) {
  try {
    const auto j = nlohmann::json::parse(json);
    if (const auto k = j.find("kernel"); k != j.end()) {
      scene.kernel = k->get<std::string>();
      contact::makeKernel(scene.kernel);  // throws for a name this build does not know
    }
    if (const auto m = j.find("contact_model"); m != j.end()) {
      scene.contact_model = m->get<std::string>();
      if (const std::string unknown = setup::unknownContactModel(scene.contact_model);
          !unknown.empty()) {
        throw Error(unknown);
      }
    }
  } catch (const std::exception& e) {
    throw CheckpointError(cat(file, ": /run/state: ", e.what()));
  }
}

void prepareContinuation(const sim::CheckpointData& data, const std::string& file,
                         setup::Setup& scene) {
  if (data.format_version < checkpoint::kFirstDigestCheckpointVersion) {
    log::warning(cat(file, ": format version ", data.format_version,
                     " predates the whole-file digest; its datasets' checksums were verified, but ",
                     "an edit that kept them consistent cannot be detected"));
  }
  restoreRunSettings(data.run_state, file, scene);
  if (data.format_version < 2 && scene.contact_model != "point") {
    // Continuing with another model would not continue that run.
    log::info(cat(file, ": format version ", data.format_version,
                  " predates sub-contacts; continuing with contact_model = \"point\""));
    scene.contact_model = "point";
  }
  if (data.format_version < 4 && !scene.joints.empty()) {
    log::info(cat(file, ": format version ", data.format_version,
                  " predates joint planes; continuing without joints (material pairs only)"));
  }
}

void restoreRunState(const std::string& json, const std::string& file, Tracker& tracker,
                     std::vector<std::unique_ptr<Check>>& checks) {
  try {
    const auto j = nlohmann::json::parse(json);
    tracker.restoreInitial(
        fromBits(j.at("tracker_initial_bits").get<std::vector<std::uint64_t>>()));
    const auto& c = j.at("checks_bits");
    for (auto& check : checks) {
      const auto it = c.find(check->spec().name);
      if (it == c.end()) {
        throw Error(cat("no state for [[check]] '", check->spec().name, "'"));
      }
      const auto state = fromBits(it->get<std::vector<std::uint64_t>>());
      if (state.size() != check->state().size()) {
        throw Error(cat("[[check]] '", check->spec().name, "' has ", state.size(),
                        " stored values, expected ", check->state().size()));
      }
      check->restore(state);
    }
  } catch (const std::exception& e) {
    throw CheckpointError(cat(file, ": /run/state does not fit the scene: ", e.what()));
  }
}

CheckpointSchedule::CheckpointSchedule(const setup::CheckpointSpec& spec, std::filesystem::path dir,
                                       std::string scene_toml, std::string scene_file,
                                       std::string code_version, const Tracker& tracker,
                                       const std::vector<std::unique_ptr<Check>>& checks,
                                       MPI_Comm comm)
    : spec_(spec),
      dir_(std::move(dir)),
      scene_toml_(std::move(scene_toml)),
      scene_file_(std::move(scene_file)),
      code_version_(std::move(code_version)),
      tracker_(tracker),
      checks_(checks),
      comm_(comm) {
  if (dir_.empty()) return;
  drawRunId();
  if (mpi::rank(comm_) != 0) return;
  // Temporary files that a write cut short (kill -9, a crash, a node failure) left behind: only
  // files named as polydem names them, only in this run's checkpoint directory.
  for (const auto& t : checkpoint::removeStaleTemporaryCheckpoints(dir_ / "checkpoints")) {
    if (t.removed) {
      log::warning(cat("removed ", t.path.string(), " (", t.bytes,
                       " bytes), the temporary file of a checkpoint write that did not finish"));
    } else {
      log::warning(cat("left ", t.path.string(), ": the temporary file of a checkpoint write by ",
                       t.writer_alive ? cat("process ", t.pid, ", which is still running")
                                      : std::string("a process that is gone (cannot remove it)")));
    }
  }
}

void CheckpointSchedule::drawRunId() {
  char id[checkpoint::kCheckpointRunIdDigits + 1] = {};
  if (mpi::rank(comm_) == 0) {
    const std::string drawn = checkpoint::newCheckpointRunId(dir_ / "checkpoints");
    drawn.copy(id, checkpoint::kCheckpointRunIdDigits);
  }
  MPI_Bcast(id, checkpoint::kCheckpointRunIdDigits, MPI_CHAR, 0, comm_);
  run_id_ = id;
}

bool CheckpointSchedule::afterStep(sim::Simulation& sim) {
  const bool by_steps = spec_.every_steps > 0 && runSteps(sim) % spec_.every_steps == 0;
  bool by_wall = false;
  if (mpi::rank(comm_) == 0 && spec_.every_seconds > 0.0) {
    const auto now = std::chrono::steady_clock::now();
    by_wall = std::chrono::duration<double>(now - last_wall_).count() >= spec_.every_seconds;
  }
  // One allreduce: any rank's signal, and rank 0's clock.
  int local[2] = {stopSignalReceived(), by_wall ? 1 : 0};
  int global[2] = {0, 0};
  MPI_Allreduce(local, global, 2, MPI_INT, MPI_MAX, comm_);
  if (global[0] != 0) {
    stop_signal_ = global[0];
    return true;  // the caller writes the checkpoint once the stage has stopped
  }
  if (dir_.empty() || !(by_steps || global[1] != 0)) return false;
  // A checkpoint in the equilibrium stage at the step where the force ratio ends it would,
  // restarted, take one more equilibrium step: that step's checkpoint is left out.
  if (sim.stage() == sim::Stage::kEquilibrium &&
      sim.forceRatio() < sim.scene().equilibrium.force_ratio) {
    return false;
  }
  write(sim);
  return false;
}

bool CheckpointSchedule::signalAfterRun() {
  if (stop_signal_ != 0) return false;
  int local = stopSignalReceived(), global = 0;
  MPI_Allreduce(&local, &global, 1, MPI_INT, MPI_MAX, comm_);
  stop_signal_ = global;
  return global != 0;
}

// Timed in the running loop's pool as a row of its own (a write inside the stop check is not
// counted as checking).
std::filesystem::path CheckpointSchedule::write(sim::Simulation& sim) {
  const TimingPool::Scope timer(sim.loop().timing(), "(checkpoint)");
  const auto path = checkpoint::checkpointFileName(dir_ / "checkpoints", runSteps(sim), run_id_);
  if (mpi::rank(comm_) == 0) std::filesystem::create_directories(path.parent_path());
  MPI_Barrier(comm_);
  sim::CheckpointData data = sim.checkpointForWriting(scene_toml_, scene_file_,
                                                      runStateJson(sim.scene(), tracker_, checks_));
  data.code_version = code_version_;
  checkpoint::writeCheckpoint(path, data, comm_);
  if (mpi::rank(comm_) == 0) {
    checkpoint::pruneCheckpoints(path.parent_path(), run_id_, spec_.keep);  // this run's files only
    log::info(cat(
        "checkpoint ", path.string(), " (",
        sim::toString(sim.stage() == sim::Stage::kEquilibrium ? sim::CheckpointStage::kEquilibrium
                                                              : sim::CheckpointStage::kMain),
        " stage, step ", sim.stepCount(), ")"));
  }
  last_ = path;
  last_wall_ = std::chrono::steady_clock::now();
  return path;
}

}  // namespace polydem::run
