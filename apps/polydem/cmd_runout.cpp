// polydem runout SCENE --out DIR: runs a scene until its blocks are at rest (or a time cap) and
// reports the runout and the deposit (run/runout.h); --resume DIR continues one a signal stopped.
#include <cstdio>
#include <filesystem>
#include <optional>

#include "commands.h"
#include "polydem/checkpoint/checkpoint.h"
#include "polydem/core/error.h"
#include "polydem/core/logging.h"
#include "polydem/core/mpi_env.h"
#include "polydem/core/strings.h"
#include "polydem/output/output_file.h"
#include "polydem/output/output_lock.h"
#include "polydem/run/run_checkpoint.h"
#include "polydem/scene/scene_reader.h"
#include "polydem/sim/simulation.h"
#include "runout_files.h"

namespace polydem::app {

namespace {

void runoutUsage() {
  std::printf(
      "usage: [mpirun -n N] polydem runout SCENE.toml --out DIR [options]\n"
      "       [mpirun -n N] polydem runout --resume DIR [--time-cap T]\n"
      "Runs the scene (its initial-equilibrium stage first, if it has one) until every free\n"
      "block is at rest, or the time cap, and writes DIR/runout.json (runout distance of the\n"
      "failed mass's front, largest block travel, the deposit's area, length, width and volume),\n"
      "DIR/thickness.csv and thickness.png (the deposit's thickness above the ground on a\n"
      "horizontal grid) and DIR/runout_series.csv. SIGTERM/SIGUSR1 stop it with a checkpoint\n"
      "(DIR/runout.h5) that --resume DIR continues, the same bits as a run that never stopped.\n"
      "  --time-cap T          simulated seconds of run-on at most (default: the scene's\n"
      "                        end_time); with --resume, a new cap for the continued run\n"
      "  --check-every N       steps between checks of rest (default 100)\n"
      "  --cell H              the thickness map's cell, m (default: 1/4 of the median size of\n"
      "                        the failed blocks)\n"
      "  --checkpoint-every N  steps between checkpoints (default: [checkpoint] every_steps)\n"
      "  --quiet               only the result, warnings and errors\n");
}

// The result's files and line (rank 0), agreed failure on every rank.
void report(const std::string& out, const run::RunoutResult& r) {
  const std::string resume = r.checkpoint.empty() ? std::string()
                                                  : cat("mpirun -n ", mpi::size(), " ",
                                                        programPath(), " runout --resume ", out);
  std::string error;
  if (mpi::rank() == 0) {
    try {
      writeRunoutFiles(out, r, resume);
      std::printf("%s\n", runoutLine(r, out).c_str());
      if (!resume.empty()) std::printf("to continue: %s\n", resume.c_str());
    } catch (const Error& e) {
      error = e.what();
    }
  }
  output::throwIfAnyRankFailed(error, MPI_COMM_WORLD);
}

}  // namespace

RunoutOptions runoutOptions(Args& args, const std::string& prefix) {
  RunoutOptions o;
  if (args.value(prefix + "time-cap") || args.value(prefix + "time")) {
    o.time_cap = args.value(prefix + "time-cap") ? args.number(prefix + "time-cap", 0.0)
                                                 : args.number(prefix + "time", 0.0);
    if (!(*o.time_cap > 0.0)) throw UsageError("the run-on's time cap must be > 0");
  }
  o.check_every = args.integer(prefix + "check-every", 100, 1);
  o.cell = args.number(prefix + "cell", 0.0, 0.0);
  if (args.value(prefix + "checkpoint-every")) {
    o.checkpoint_every = args.integer(prefix + "checkpoint-every", 0, 0, Args::kInt64Max);
  }
  return o;
}

int runoutCommand(int argc, char** argv) {
  Args args(argc, argv, {"help", "quiet"});
  const auto resume = args.value("resume");
  if (args.flag("help") || args.positional().size() != (resume ? 0u : 1u)) {
    runoutUsage();
    return args.flag("help") ? 0 : 2;
  }
  if (args.flag("quiet")) log::setLevel(log::Level::kWarning);
  if (resume) {
    const std::string out = *resume;
    // Only the cap may change on a resume: it decides when the run stops, never its states.
    std::optional<double> cap;
    if (args.value("time-cap")) cap = args.number("time-cap", 0.0);
    if (cap && !(*cap > 0.0)) throw UsageError("the run-on's time cap must be > 0");
    args.rejectUnknown();
    const std::string file = out + "/runout.h5";
    const sim::CheckpointData data = checkpoint::readCheckpoint(file, MPI_COMM_WORLD);
    setup::Setup scene = scene::parseScene(data.scene_toml, data.scene_file);
    run::prepareContinuation(data, file, scene);
    run::RunoutSettings settings;
    const run::RunoutProgress progress = run::runoutStateFrom(data.run_state, file, settings);
    if (cap) settings.time_cap = *cap;
    settings.dir = out;
    settings.scene_text = data.scene_toml;
    settings.scene_file = data.scene_file;
    const output::OutputLock lock(out, MPI_COMM_WORLD);
    sim::Simulation sim(scene, data, file, MPI_COMM_WORLD);
    report(out, run::runRunout(sim, settings, progress));
    return 0;
  }
  const std::string out = args.value("out", "");
  if (out.empty()) throw UsageError("polydem runout needs --out DIR");
  const RunoutOptions options = runoutOptions(args, "");
  args.rejectUnknown();
  const setup::Setup scene = scene::readScene(args.positional()[0]);
  const run::RunoutSettings settings = runoutSettings(scene, options, out);
  const output::OutputLock lock(out, MPI_COMM_WORLD);
  sim::Simulation sim(scene, MPI_COMM_WORLD);
  sim.runEquilibrium();
  log::info(cat("runout: ", scene.id, " (", scene.file, ") until at rest or ",
                num(settings.time_cap), " s, into ", out));
  run::RunoutProgress progress;
  progress.start_time = sim.time();
  report(out, run::runRunout(sim, settings, progress));
  return 0;
}

}  // namespace polydem::app
