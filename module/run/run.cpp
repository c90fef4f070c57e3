#include "polydem/run/run.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>

#include "polydem/checkpoint/checkpoint.h"
#include "polydem/contact/contact.h"
#include "polydem/core/error.h"
#include "polydem/core/logging.h"
#include "polydem/core/mpi_env.h"
#include "polydem/core/state_hash.h"
#include "polydem/core/strings.h"
#include "polydem/core/test_pause.h"
#include "polydem/output/output_file.h"
#include "polydem/output/output_lock.h"
#include "polydem/run/checks.h"
#include "polydem/run/run_checkpoint.h"
#include "polydem/run/run_output.h"
#include "polydem/scene/scene_reader.h"
#include "polydem/sim/balance_figures.h"
#include "polydem/sim/simulation.h"

namespace polydem::run {

namespace {

nlohmann::json summaryJson(const setup::Setup& scene, sim::Simulation& sim, const RunResult& result,
                           timeloop::StopReason reason, const std::vector<TimingPool::Reduced>& t) {
  using nlohmann::json;
  const auto& stats = sim.contactStats();
  json j;
  j["scene"] = scene.id;
  j["title"] = scene.title;
  j["scene_file"] = scene.file;
  j["kernel"] = scene.kernel;
  j["contact_model"] = scene.contact_model;
  j["broadphase"] = scene.broadphase;
  j["ranks"] = mpi::size(sim.comm());
  j["dt"] = scene.dt;
  j["suggested_dt"] = sim.suggestedTimeStep();
  j["steps"] = result.steps;
  j["time"] = result.time;
  j["wall_seconds"] = result.wall_seconds;
  j["stop_reason"] = timeloop::toString(reason);
  if (scene.equilibrium.enabled) {
    j["equilibrium"] = {{"steps", result.equilibrium_steps},
                        {"reached", sim.equilibriumReached()},
                        {"force_ratio", scene.equilibrium.force_ratio}};
  }
  j["particles"] = result.hash.particle_count;  // every particle once, replicated ones too
  j["last_step"] = {{"candidate_pairs", stats.candidates}, {"evaluated_pairs", stats.evaluated},
                    {"touching_pairs", stats.touching},    {"not_converged", stats.not_converged},
                    {"degenerate", stats.degenerate},      {"inner_domain", stats.inner_domain}};
  j["timing"] = output::timingJson(t, result.steps);
  j["checks"] = output::checksJson(result.checks);
  j["state_hash"] = result.hash.hex();
  j["state"] = {{"particles_hash", BitHasher::hex(result.hash.particles)},
                {"history_hash", BitHasher::hex(result.hash.history)},
                {"particles", result.hash.particle_count},
                {"pairs", result.hash.pair_count},
                {"history_conflicts", result.hash.history_conflicts}};
  return j;
}

// " m" after a value in metres; nothing for a ratio ("1") or a check without a unit.
std::string unitSuffix(const std::string& unit) {
  return unit.empty() || unit == "1" ? std::string() : " " + unit;
}

// One line a check: PASS/FAIL with what the value was compared against, or REPORT for a check
// that only reports its value (compare = "report": it cannot fail, so it says neither).
void printChecks(const std::vector<output::CheckResult>& checks) {
  if (checks.empty()) return;
  log::info("checks:");
  for (const auto& c : checks) {
    const std::string unit = unitSuffix(c.unit);
    const std::string note = c.note.empty() ? "" : "  [" + c.note + "]";
    if (c.compare == "report") {
      log::info(cat("  REPORT ", c.name, ": ", num(c.value), unit, note));
      continue;
    }
    const bool tol = c.compare == "abs" || c.compare == "rel";
    log::info(cat("  ", c.pass ? "PASS " : "FAIL ", c.name, ": ", num(c.value), unit, " (",
                  c.compare, " ", num(c.expected), tol ? " +- " + num(c.tolerance) : std::string(),
                  ")", note));
  }
}

}  // namespace

bool RunResult::all_checks_pass() const {
  for (const auto& c : checks) {
    if (!c.pass) return false;
  }
  return true;
}

void applyOverrides(setup::Setup& scene, const RunOptions& options) {
  if (options.kernel) {
    contact::makeKernel(*options.kernel);  // throws with the list of known kernels
    scene.kernel = *options.kernel;
  }
  if (options.contact_model) {
    if (const auto e = setup::unknownContactModel(*options.contact_model); !e.empty())
      throw Error(e);
    scene.contact_model = *options.contact_model;
  }
  if (options.steps || options.end_time) {
    scene.steps = options.steps;
    scene.end_time = options.end_time;
  }
}

namespace {

// Communication volume of the whole run, all ranks (collective).
nlohmann::json communicationJson(const sim::Simulation& sim, MPI_Comm comm) {
  const auto& totals = sim.exchangeTotals();
  std::int64_t sent[3] = {totals.bytes_sent, totals.particles_sent, totals.histories_sent};
  MPI_Allreduce(MPI_IN_PLACE, sent, 3, MPI_INT64_T, MPI_SUM, comm);
  return {{"bytes_sent", sent[0]}, {"particles_sent", sent[1]}, {"histories_sent", sent[2]}};
}

nlohmann::json rebalancingJson(const sim::BalanceLog& log) {
  return {{"balance_checks", log.checks},
          {"new_decompositions_computed", log.proposals},
          {"new_decompositions_adopted", log.adopted},
          {"work_imbalance_at_last_check", log.last_imbalance}};
}

setup::CheckpointSpec checkpointSpec(const setup::Setup& scene, const RunOptions& options) {
  setup::CheckpointSpec spec = scene.checkpoint;
  if (options.checkpoint_every) spec.every_steps = *options.checkpoint_every;
  if (options.checkpoint_seconds) spec.every_seconds = *options.checkpoint_seconds;
  if (options.checkpoint_keep) spec.keep = *options.checkpoint_keep;
  return spec;
}

// One run of a scene, new or the continuation of a checkpoint's: run() reads as the algorithm
// (set-up, stages, output, checks, summary); each piece is a method below.
class SceneRun {
 public:
  SceneRun(setup::Setup scene, const RunOptions& options, MPI_Comm comm,
           const sim::CheckpointData* restart, sim::HistoryChunks* histories,
           const std::string& restart_file)
      : scene_(std::move(scene)),
        options_(options),
        comm_(comm),
        restart_(restart),
        histories_(histories),
        restart_file_(restart_file) {}

  RunResult run() {
    buildSimulation();
    setUpObservers();
    const auto reason = runStages();
    closeOutput();
    checkpointOnSignal();
    measure();
    const auto timing = sim_->loop().timing().reduce(comm_);
    printResults(reason, timing);
    writeSummary(reason, timing);
    printEnd();
    return result_;
  }

 private:
  bool writes() const { return !options_.out_dir.empty(); }
  // The scene, from the simulation's copy once it is built.
  const setup::Setup& scene() const { return sim_ ? sim_->scene() : scene_; }
  bool rankZero() const { return mpi::rank(comm_) == 0; }

  // The simulation, from the scene or the checkpoint, with its progress line.
  void buildSimulation() {
    // One run per output folder: held until this run's last file is written (output_lock.h).
    if (writes()) lock_.emplace(options_.out_dir, comm_);
    wall0_ = std::chrono::steady_clock::now();
    log::info(cat("scene ", scene_.id, " (", scene_.file, "): ", scene_.particles.size(),
                  " particles, kernel ", scene_.kernel, ", ", mpi::size(comm_), " rank(s)"));
    sim_ = restart_ ? std::make_unique<sim::Simulation>(scene_, *restart_, *histories_,
                                                        restart_file_, comm_)
                    : std::make_unique<sim::Simulation>(scene_, comm_);
    // The simulation keeps a copy (scene()): this one would be a second, on every rank, of a
    // list as long as the particles.
    scene_ = setup::Setup();
    const std::int64_t every =
        options_.progress_every > 0 ? options_.progress_every : scene().output.progress_every;
    sim_->loop().setProgressInterval(every, every > 0 ? 0.0 : 5.0);
  }

  // The checks, the monitored particles, the checkpoint schedule as the step hook.
  void setUpObservers() {
    checks_ = makeChecks(scene(), tracker_);
    for (const auto& label : scene().output.monitor) {
      const Uid uid = uidOfLabel(scene(), label);
      tracker_.track(uid);
      monitored_.emplace_back(uid, label);
    }
    if (restart_) restoreRunState(restart_->run_state, restart_file_, tracker_, checks_);
    const std::string scene_text =
        options_.scene_text.empty() && restart_ ? restart_->scene_toml : options_.scene_text;
    schedule_ = std::make_unique<CheckpointSchedule>(
        checkpointSpec(scene(), options_), options_.out_dir, scene_text, scene().file,
        options_.code_version, tracker_, checks_, comm_);
    if (options_.stop_on_signals) installStopSignals();
    sim_->setStepHook([this] { return schedule_->afterStep(*sim_); });
    sim_->keepContactRecords(readsContactRecords());
  }

  // Whether anything of this run reads the contact phase's full records: the snapshots' contacts
  // and contact sums (the first and last snapshots at least, whatever step the run stops at), the
  // tracked particles' contact counts, checks on contact forces. Without a reader the records are
  // not kept (sim::ContactPhase::keepRecords).
  bool readsContactRecords() const {
    if (writes() && options_.snapshots) return true;
    if (!tracker_.empty()) return true;
    return std::any_of(checks_.begin(), checks_.end(),
                       [](const auto& c) { return c->readsContacts(); });
  }

  // The equilibrium stage, then the output's first rows and the main stage with its observers.
  timeloop::StopReason runStages() {
    sim::Simulation& sim = *sim_;
    result_.equilibrium_steps = sim.runEquilibrium();
    const bool stopped_early = schedule_->stopSignal() != 0;
    if (!tracker_.empty() && sim.stage() == sim::Stage::kMain) tracker_.gather(sim);
    openOutput();
    sim.addObserver([this] { observeStep(); });
    if (stopped_early) return timeloop::StopReason::kUserCondition;
    return sim.run();
  }

  void openOutput() {
    if (!writes()) return;
    output_ = std::make_unique<RunOutput>(options_.out_dir, *sim_, tracker_, monitored_, checks_,
                                          options_.snapshots);
    output_->writeSeries(*sim_, tracker_, checks_);
    output_->writeSnapshot(*sim_);
  }

  // After every step of the main stage: the checks, a series row and a snapshot when due.
  void observeStep() {
    sim::Simulation& sim = *sim_;
    if (!tracker_.empty()) tracker_.gather(sim);
    for (auto& c : checks_) c->observe(sim, tracker_);
    if (!output_) return;
    const std::int64_t step = sim.stepCount();  // the step just completed (observers run after it)
    const std::int64_t series_every = std::max<std::int64_t>(1, scene().output.series_every);
    const std::int64_t snapshot_every = scene().output.snapshot_every;
    if (step % series_every == 0) output_->writeSeries(sim, tracker_, checks_);
    if (snapshot_every > 0 && step % snapshot_every == 0) output_->writeSnapshot(sim);
  }

  void closeOutput() {
    testPause("after-run");  // test hook (core/test_pause.h)
    if (!output_) return;
    // The final state, unless the observer has just written it (or nothing has happened since
    // the rows written at the start).
    output_->writeSeriesOnce(*sim_, tracker_, checks_);
    output_->writeSnapshotOnce(*sim_);
    output_->close();
  }

  // A signal that came after the last step's check (during the final outputs) still ends in a
  // checkpoint, of the final state: whenever a run is signalled, it leaves one.
  void checkpointOnSignal() {
    result_.signal_after_end = schedule_->signalAfterRun();
    if (schedule_->stopSignal() == 0) return;
    result_.stop_signal = signalName(schedule_->stopSignal());
    if (writes()) result_.checkpoint = schedule_->write(*sim_).string();
  }

  void measure() {
    result_.checks = evaluateChecks(checks_, *sim_);
    result_.hash = sim_->stateHash();
    result_.steps = sim_->stepCount();
    result_.time = sim_->time();
    result_.wall_seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0_).count();
  }

  void printResults(timeloop::StopReason reason, const std::vector<TimingPool::Reduced>& timing) {
    log::info(cat("finished: ", timeloop::toString(reason), " after ", result_.steps,
                  " steps, t = ", num(result_.time), " s, ", num(result_.wall_seconds), " s wall"));
    log::info(TimingPool::table(timing, result_.steps));
    printChecks(result_.checks);
    log::info("state hash " + result_.hash.hex());
    if (result_.hash.history_conflicts != 0) {
      log::warning(cat(result_.hash.history_conflicts,
                       " pair histories differ between ranks: please report this as a bug"));
    }
  }

  // summary.json (rank 0 writes it; every rank ends if it cannot). The communication and balance
  // figures are collective, so every rank computes them.
  void writeSummary(timeloop::StopReason reason, const std::vector<TimingPool::Reduced>& timing) {
    const nlohmann::json communication = communicationJson(*sim_, comm_);
    const nlohmann::json balance = sim::toJson(sim::balanceFigures(*sim_));
    if (!writes()) return;
    std::string summary_error;
    if (rankZero()) {
      auto summary = summaryJson(scene(), *sim_, result_, reason, timing);
      addRunFacts(summary);
      summary["communication"] = communication;
      summary["balance"] = balance["balance"];
      summary["balance"]["rebalancing"] = rebalancingJson(sim_->balanceLog());
      summary["communication_seconds_per_step"] = balance["communication_seconds_per_step"];
      try {
        output::writeJsonAtomic(options_.out_dir + "/summary.json", summary);
      } catch (const Error& e) {
        summary_error = e.what();
      }
    }
    output::throwIfAnyRankFailed(summary_error, comm_);
  }

  // How the run ended and where it continues: signals, checkpoint, restart.
  void addRunFacts(nlohmann::json& summary) const {
    summary["stopped_by_signal"] =
        result_.stopped_early() ? nlohmann::json(result_.stop_signal) : nlohmann::json();
    if (result_.signal_after_end) summary["signal_after_end"] = result_.stop_signal;
    if (!result_.checkpoint.empty()) summary["checkpoint"] = result_.checkpoint;
    if (restart_) summary["restarted_from"] = restart_file_;
    summary["checkpoint_run_id"] = schedule_->runId();  // in the names of this run's checkpoints
  }

  // The files written, and for a signalled run where its checkpoint is and how to continue.
  void printEnd() const {
    if (!rankZero()) return;
    if (writes()) {
      log::info("wrote " + options_.out_dir + "/summary.json, series.csv" +
                (!options_.snapshots                       ? ""
                 : scene().output.snapshot_format == "vtk" ? ", snapshots.pvd, contacts.pvd"
                                                           : ", snapshots.xmf, contacts.xmf"));
    }
    if (result_.stop_signal.empty()) return;
    const std::string where =
        result_.checkpoint.empty() ? std::string("no checkpoint (no --out)") : result_.checkpoint;
    if (result_.signal_after_end) {
      log::info(cat(result_.stop_signal, " received after the last step (the run is complete); ",
                    "checkpoint of the final state: ", where));
    } else {
      log::info(cat("stopped by ", result_.stop_signal, " at the end of ",
                    sim_->stage() == sim::Stage::kEquilibrium ? "equilibrium" : "main", " step ",
                    result_.steps, "; checkpoint: ", where));
    }
    if (result_.checkpoint.empty()) return;
    log::info(cat("to continue: mpirun -n ", mpi::size(comm_), " ", options_.program,
                  " run --restart ", result_.checkpoint, " --out ", options_.out_dir,
                  result_.signal_after_end ? " --end-time T (or --steps N) beyond the end" : "",
                  "  (any rank count; use another --out to keep this part's files)"));
  }

  setup::Setup scene_;  // released once the simulation holds its copy
  const RunOptions& options_;
  MPI_Comm comm_;
  const sim::CheckpointData* restart_;  // null: a new run
  sim::HistoryChunks* histories_;       // the restart's pair histories, handed over in chunks
  const std::string& restart_file_;
  std::optional<output::OutputLock> lock_;
  std::chrono::steady_clock::time_point wall0_;
  std::unique_ptr<sim::Simulation> sim_;
  Tracker tracker_;
  std::vector<std::unique_ptr<Check>> checks_;
  std::vector<std::pair<Uid, std::string>> monitored_;
  std::unique_ptr<CheckpointSchedule> schedule_;
  std::unique_ptr<RunOutput> output_;
  RunResult result_;
};

// A new run (`restart` null) or the continuation of a checkpoint's.
RunResult runWith(setup::Setup scene, const RunOptions& options, MPI_Comm comm,
                  const sim::CheckpointData* restart, sim::HistoryChunks* histories,
                  const std::string& restart_file) {
  applyOverrides(scene, options);
  sim::requireStopCondition(scene);  // before anything is built or written
  SceneRun run(std::move(scene), options, comm, restart, histories, restart_file);
  return run.run();
}

}  // namespace

RunResult runScene(setup::Setup scene, const RunOptions& options, MPI_Comm comm) {
  return runWith(std::move(scene), options, comm, nullptr, nullptr, "");
}

RunResult continueRun(const std::string& file, const std::optional<std::string>& scene_file,
                      RunOptions options, MPI_Comm comm) {
  // Everything but the pair histories now; those in chunks while the simulation is built.
  checkpoint::CheckpointReader reader(file, comm);
  const sim::CheckpointData& data = reader.data();
  setup::Setup scene;
  if (scene_file) {
    const std::string text = scene::readSceneText(*scene_file);
    const std::string diff =
        scene::sceneDifference(data.scene_toml, data.scene_file, text, *scene_file);
    if (!diff.empty()) {
      throw CheckpointError(cat(file, ": scene ", *scene_file, " differs from the scene stored in ",
                                "the checkpoint (", data.scene_file, ") in ", diff,
                                "; only [simulation] end_time/steps, [output], [checkpoint] and ",
                                "[kernel_params] separating_axes may change when a run continues"));
    }
    scene = scene::parseScene(text, *scene_file);
    options.scene_text = text;  // later checkpoints store the scene this part runs
  } else {
    scene = scene::parseScene(data.scene_toml, data.scene_file);
    options.scene_text = data.scene_toml;
  }
  // The kernel and contact model the run used (a command line may have set them over the scene).
  prepareContinuation(data, file, scene);
  return runWith(std::move(scene), options, comm, &data, &reader, file);
}

}  // namespace polydem::run
