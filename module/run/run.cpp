#include "polydem/run/run.h"

#include <chrono>
#include <cstdio>
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

setup::CheckpointSpec checkpointSpec(const setup::Setup& scene, const RunOptions& options) {
  setup::CheckpointSpec spec = scene.checkpoint;
  if (options.checkpoint_every) spec.every_steps = *options.checkpoint_every;
  if (options.checkpoint_seconds) spec.every_seconds = *options.checkpoint_seconds;
  if (options.checkpoint_keep) spec.keep = *options.checkpoint_keep;
  return spec;
}

// A new run (`restart` null) or the continuation of a checkpoint's.
RunResult runWith(setup::Setup scene, const RunOptions& options, MPI_Comm comm,
                  const sim::CheckpointData* restart, sim::HistoryChunks* histories,
                  const std::string& restart_file) {
  applyOverrides(scene, options);
  sim::requireStopCondition(scene);  // before anything is built or written
  // One run per output folder: held until this run's last file is written (output_lock.h).
  std::optional<output::OutputLock> lock;
  if (!options.out_dir.empty()) lock.emplace(options.out_dir, comm);
  const auto wall0 = std::chrono::steady_clock::now();
  log::info(cat("scene ", scene.id, " (", scene.file, "): ", scene.particles.size(),
                " particles, kernel ", scene.kernel, ", ", mpi::size(comm), " rank(s)"));
  const auto sim_ptr =
      restart ? std::make_unique<sim::Simulation>(scene, *restart, *histories, restart_file, comm)
              : std::make_unique<sim::Simulation>(scene, comm);
  sim::Simulation& sim = *sim_ptr;
  const std::int64_t every =
      options.progress_every > 0 ? options.progress_every : scene.output.progress_every;
  sim.loop().setProgressInterval(every, every > 0 ? 0.0 : 5.0);

  Tracker tracker;
  auto checks = makeChecks(scene, tracker);
  std::vector<std::pair<Uid, std::string>> monitored;
  for (const auto& label : scene.output.monitor) {
    const Uid uid = uidOfLabel(scene, label);
    tracker.track(uid);
    monitored.emplace_back(uid, label);
  }
  if (restart) restoreRunState(restart->run_state, restart_file, tracker, checks);
  const std::string scene_text =
      options.scene_text.empty() && restart ? restart->scene_toml : options.scene_text;
  CheckpointSchedule schedule(checkpointSpec(scene, options), options.out_dir, scene_text,
                              scene.file, options.code_version, tracker, checks, comm);
  if (options.stop_on_signals) installStopSignals();
  sim.setStepHook([&] { return schedule.afterStep(sim); });

  RunResult result;
  result.equilibrium_steps = sim.runEquilibrium();
  auto reason = timeloop::StopReason::kUserCondition;
  const bool stopped_early = schedule.stopSignal() != 0;
  if (!tracker.empty() && sim.stage() == sim::Stage::kMain)
    tracker.gather(sim);  // main stage start

  std::unique_ptr<RunOutput> output;
  if (!options.out_dir.empty()) {
    output = std::make_unique<RunOutput>(options.out_dir, sim, tracker, monitored, checks,
                                         options.snapshots);
    output->writeSeries(sim, tracker, checks);
    output->writeSnapshot(sim);
  }
  const std::int64_t series_every = std::max<std::int64_t>(1, scene.output.series_every);
  const std::int64_t snapshot_every = scene.output.snapshot_every;
  sim.addObserver([&] {
    if (!tracker.empty()) tracker.gather(sim);
    for (auto& c : checks) c->observe(sim, tracker);
    if (!output) return;
    const std::int64_t step = sim.stepCount();  // the step just completed (observers run after it)
    if (step % series_every == 0) output->writeSeries(sim, tracker, checks);
    if (snapshot_every > 0 && step % snapshot_every == 0) output->writeSnapshot(sim);
  });
  if (!stopped_early) reason = sim.run();
  testPause("after-run");  // test hook (core/test_pause.h)
  if (output) {
    // The final state, unless the observer has just written it (or nothing has happened since
    // the rows written at the start).
    output->writeSeriesOnce(sim, tracker, checks);
    output->writeSnapshotOnce(sim);
    output->close();
  }
  // A signal that came after the last step's check (during the final outputs) still ends in a
  // checkpoint, of the final state: whenever a run is signalled, it leaves one.
  result.signal_after_end = schedule.signalAfterRun();
  if (schedule.stopSignal() != 0) {
    result.stop_signal = signalName(schedule.stopSignal());
    if (!options.out_dir.empty()) result.checkpoint = schedule.write(sim).string();
  }

  result.checks = evaluateChecks(checks, sim);
  result.hash = sim.stateHash();
  result.steps = sim.stepCount();
  result.time = sim.time();
  result.wall_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  const auto timing = sim.loop().timing().reduce(comm);
  log::info(cat("finished: ", timeloop::toString(reason), " after ", result.steps,
                " steps, t = ", num(result.time), " s, ", num(result.wall_seconds), " s wall"));
  log::info(TimingPool::table(timing, result.steps));
  printChecks(result.checks);
  log::info("state hash " + result.hash.hex());
  if (result.hash.history_conflicts != 0) {
    log::warning(cat(result.hash.history_conflicts,
                     " pair histories differ between ranks: please report this as a bug"));
  }
  // Communication volume of the whole run, all ranks (collective, so outside the rank-0 branch).
  const auto& totals = sim.exchangeTotals();
  std::int64_t sent[3] = {totals.bytes_sent, totals.particles_sent, totals.histories_sent};
  MPI_Allreduce(MPI_IN_PLACE, sent, 3, MPI_INT64_T, MPI_SUM, comm);
  const nlohmann::json communication = {
      {"bytes_sent", sent[0]}, {"particles_sent", sent[1]}, {"histories_sent", sent[2]}};
  const nlohmann::json balance = sim::toJson(sim::balanceFigures(sim));
  const auto& log = sim.balanceLog();
  const nlohmann::json decomposition = {{"balance_checks", log.checks},
                                        {"new_decompositions_computed", log.proposals},
                                        {"new_decompositions_adopted", log.adopted},
                                        {"work_imbalance_at_last_check", log.last_imbalance}};
  std::string summary_error;  // rank 0 writes summary.json; every rank ends if it cannot
  if (!options.out_dir.empty() && mpi::rank(comm) == 0) {
    auto summary = summaryJson(scene, sim, result, reason, timing);
    summary["stopped_by_signal"] =
        result.stopped_early() ? nlohmann::json(result.stop_signal) : nlohmann::json();
    if (result.signal_after_end) summary["signal_after_end"] = result.stop_signal;
    if (!result.checkpoint.empty()) summary["checkpoint"] = result.checkpoint;
    if (restart) summary["restarted_from"] = restart_file;
    summary["checkpoint_run_id"] = schedule.runId();  // in the names of this run's checkpoints
    summary["communication"] = communication;
    summary["balance"] = balance["balance"];
    summary["balance"]["rebalancing"] = decomposition;
    summary["communication_seconds_per_step"] = balance["communication_seconds_per_step"];
    try {
      output::writeJsonAtomic(options.out_dir + "/summary.json", summary);
    } catch (const Error& e) {
      summary_error = e.what();
    }
  }
  if (!options.out_dir.empty()) output::throwIfAnyRankFailed(summary_error, comm);
  if (!options.out_dir.empty() && mpi::rank(comm) == 0) {
    log::info("wrote " + options.out_dir + "/summary.json, series.csv" +
              (!options.snapshots                      ? ""
               : scene.output.snapshot_format == "vtk" ? ", snapshots.pvd, contacts.pvd"
                                                       : ", snapshots.xmf, contacts.xmf"));
  }
  if (!result.stop_signal.empty() && mpi::rank(comm) == 0) {
    const std::string where =
        result.checkpoint.empty() ? std::string("no checkpoint (no --out)") : result.checkpoint;
    if (result.signal_after_end) {
      log::info(cat(result.stop_signal, " received after the last step (the run is complete); ",
                    "checkpoint of the final state: ", where));
    } else {
      log::info(cat("stopped by ", result.stop_signal, " at the end of ",
                    sim.stage() == sim::Stage::kEquilibrium ? "equilibrium" : "main", " step ",
                    result.steps, "; checkpoint: ", where));
    }
    if (!result.checkpoint.empty()) {
      log::info(cat("to continue: mpirun -n ", mpi::size(comm), " ", options.program,
                    " run --restart ", result.checkpoint, " --out ", options.out_dir,
                    result.signal_after_end ? " --end-time T (or --steps N) beyond the end" : "",
                    "  (any rank count; use another --out to keep this part's files)"));
    }
  }
  return result;
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
