#include "sim/run.h"

#include <chrono>
#include <cstdio>
#include <nlohmann/json.hpp>

#include "contact/contact.h"
#include "core/error.h"
#include "core/logging.h"
#include "core/mpi_env.h"
#include "core/state_hash.h"
#include "core/strings.h"
#include "sim/checks.h"
#include "sim/run_output.h"
#include "sim/simulation.h"

namespace polydem::sim {

namespace {

nlohmann::json summaryJson(const io::Scene& scene, Simulation& sim, const RunResult& result,
                           timeloop::StopReason reason, const std::vector<TimingPool::Reduced>& t) {
  using nlohmann::json;
  const auto& stats = sim.contactStats();
  json j;
  j["scene"] = scene.id;
  j["title"] = scene.title;
  j["scene_file"] = scene.file;
  j["kernel"] = scene.kernel;
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
  // From the state hash (each particle once, replicated bodies too), not an allreduce: this runs
  // on rank 0 alone, where a collective call would wait for the other ranks forever.
  j["particles"] = result.hash.particle_count;
  j["last_step"] = {{"candidate_pairs", stats.candidates},
                    {"evaluated_pairs", stats.evaluated},
                    {"touching_pairs", stats.touching},
                    {"not_converged", stats.not_converged},
                    {"degenerate", stats.degenerate},
                    {"inner_domain", stats.inner_domain}};
  j["timing"] = io::timingJson(t, result.steps);
  j["checks"] = io::checksJson(result.checks);
  j["state_hash"] = result.hash.hex();
  j["state"] = {{"particles_hash", BitHasher::hex(result.hash.particles)},
                {"history_hash", BitHasher::hex(result.hash.history)},
                {"particles", result.hash.particle_count},
                {"pairs", result.hash.pair_count},
                {"history_conflicts", result.hash.history_conflicts}};
  return j;
}

void printChecks(const std::vector<io::CheckResult>& checks) {
  if (checks.empty()) return;
  log::info("checks:");
  for (const auto& c : checks) {
    const bool tol = c.compare == "abs" || c.compare == "rel";
    log::info(cat("  ", c.pass ? "PASS " : "FAIL ", c.name, ": ", num(c.value), " (", c.compare,
                  " ", num(c.expected), tol ? " +- " + num(c.tolerance) : std::string(), ")",
                  c.note.empty() ? "" : "  [" + c.note + "]"));
  }
}

}  // namespace

bool RunResult::all_checks_pass() const {
  for (const auto& c : checks) {
    if (!c.pass) return false;
  }
  return true;
}

void applyOverrides(io::Scene& scene, const RunOptions& options) {
  if (options.kernel) {
    contact::makeKernel(*options.kernel);  // throws with the list of known kernels
    scene.kernel = *options.kernel;
  }
  if (options.steps || options.end_time) {
    scene.steps = options.steps;
    scene.end_time = options.end_time;
  }
}

RunResult runScene(io::Scene scene, const RunOptions& options, MPI_Comm comm) {
  applyOverrides(scene, options);
  const auto wall0 = std::chrono::steady_clock::now();
  log::info(cat("scene ", scene.id, " (", scene.file, "): ", scene.particles.size(),
                " particles, kernel ", scene.kernel, ", ", mpi::size(comm), " rank(s)"));
  Simulation sim(scene, comm);
  const std::int64_t every = options.progress_every > 0 ? options.progress_every
                                                        : scene.output.progress_every;
  sim.loop().setProgressInterval(every, every > 0 ? 0.0 : 5.0);

  Tracker tracker;
  auto checks = makeChecks(scene, tracker);
  std::vector<std::pair<Uid, std::string>> monitored;
  for (const auto& label : scene.output.monitor) {
    const Uid uid = uidOfLabel(scene, label);
    tracker.track(uid);
    monitored.emplace_back(uid, label);
  }

  RunResult result;
  result.equilibrium_steps = sim.runEquilibrium();
  if (!tracker.empty()) tracker.gather(sim);  // the initial state of the main stage

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
    const std::int64_t step = sim.stepCount() + 1;  // the step just completed
    if (step % series_every == 0) output->writeSeries(sim, tracker, checks);
    if (snapshot_every > 0 && step % snapshot_every == 0) output->writeSnapshot(sim);
  });
  const auto reason = sim.run();
  if (output) {
    output->writeSeries(sim, tracker, checks);
    output->writeSnapshot(sim);
    output->close();
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
  if (!options.out_dir.empty() && mpi::rank(comm) == 0) {
    io::writeJsonAtomic(options.out_dir + "/summary.json",
                        summaryJson(scene, sim, result, reason, timing));
    log::info("wrote " + options.out_dir + "/summary.json, series.csv" +
              (options.snapshots ? ", snapshots.pvd" : ""));
  }
  return result;
}

}  // namespace polydem::sim
