// polydem run SCENE --out DIR: runs a scene file (on as many ranks as mpirun gives), or continues
// a run from a checkpoint (--restart FILE).
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <utility>

#include "commands.h"
#include "picture.h"
#include "polydem/core/error.h"
#include "polydem/core/logging.h"
#include "polydem/core/mpi_env.h"
#include "polydem/core/strings.h"
#include "polydem/core/test_pause.h"
#include "polydem/run/run.h"
#include "polydem/scene/scene_reader.h"

namespace polydem::app {

namespace {

/// The picture of a finished run (rank 0; the others wait, so that mpirun ends after it).
void pictureOf(const run::RunOptions& options, const PictureOptions& picture) {
  if (mpi::rank(MPI_COMM_WORLD) == 0) {
    plotSeries(options.out_dir);
    if (!options.snapshots) {
      log::warning("no frames.png: --no-snapshots");
    } else {
      renderPicture(options.out_dir, picture);
    }
  }
  MPI_Barrier(MPI_COMM_WORLD);
}

void printUsage() {
  std::printf(
      "usage: [mpirun -n N] polydem run SCENE.toml --out DIR [options]\n"
      "       [mpirun -n N] polydem run --restart CHECKPOINT.h5 [SCENE.toml] --out DIR "
      "[options]\n"
      "  --steps N         run N steps (replaces the scene's end condition)\n"
      "  --end-time T      run until simulated time T (replaces the scene's end condition)\n"
      "  --kernel NAME     use another contact kernel (polydem kernels lists them)\n"
      "  --contact-model M sub-contacts (default) or point: how penalty contacts become forces\n"
      "  --progress N      progress line every N steps (default: every 5 s)\n"
      "  --no-snapshots    do not write ParaView snapshots\n"
      "  --picture         after the run, plot series.csv to DIR/series.png and render frames\n"
      "                    of the snapshots to DIR/frames.png\n"
      "                    (also [output] picture = true; needs /usr/bin/python3, matplotlib)\n"
      "  --picture-field F the frames' colours: speed (default), displacement, pressure (the\n"
      "                    water's, per face) or joint (each face by its [[joint]], with a\n"
      "                    legend); implies --picture\n"
      "  --picture-azimuth A  view the frames from azimuth A [deg, matplotlib's: 0 from +x,\n"
      "                    90 from +y] (default: from the slope's face); implies --picture\n"
      "  --check           exit with status 3 if a check of the scene fails\n"
      "  --quiet           only warnings and errors\n"
      "  --verbose         also the detail: every load-balance check, sub-step timings\n"
      "checkpoints (docs/checkpoint.md), written to DIR/checkpoints/checkpoint_<step>_<run "
      "id>.h5:\n"
      "  --checkpoint-every N     every N steps (overrides [checkpoint] every_steps)\n"
      "  --checkpoint-seconds T   every T seconds of wall clock (overrides every_seconds)\n"
      "  --checkpoint-keep K      keep the newest K of this run's (overrides keep, default 2;\n"
      "                           other runs' files are never deleted)\n"
      "  --restart FILE    continue the run of checkpoint FILE on any rank count; the scene is\n"
      "                    the stored one, or SCENE.toml if given (it may differ only in\n"
      "                    end_time/steps, [output] and [checkpoint]); --steps/--end-time\n"
      "                    extend the run (they count from the start of the main stage)\n"
      "One run per DIR: a run holds DIR/polydem.lock; a second run into it is refused (a\n"
      "lock left by a killed run on this host is taken over).\n"
      "SIGTERM or SIGUSR1 to the ranks (or to scripts/polydem-mpirun, which forwards it): a\n"
      "checkpoint at the end of the step, then exit 0 with the command that continues the run\n"
      "(docs/checkpoint.md, 'Stopping on a signal', for mpirun, Slurm and PBS).\n"
      "writes DIR/summary.json, DIR/series.csv and DIR/snapshots.xmf, contacts.xmf (+ "
      "snapshots/;\n"
      "snapshots.pvd with [output] snapshot_format = \"vtk\"); after\n"
      "--restart they hold the continued part of the run only\n");
}

/// The run's options from the command line (the picture's are read by pictureOptions).
run::RunOptions runOptions(Args& args) {
  run::RunOptions options;
  options.out_dir = args.value("out", "");
  if (options.out_dir.empty()) throw UsageError("polydem run needs --out DIR");
  if (const auto v = args.value("steps"))
    options.steps = args.integer("steps", 0, 1, Args::kInt64Max);
  if (const auto v = args.value("end-time")) options.end_time = args.number("end-time", 0.0);
  options.kernel = args.value("kernel");
  options.contact_model = args.value("contact-model");
  options.progress_every = args.integer("progress", 0, 1, Args::kInt64Max);
  options.snapshots = !args.flag("no-snapshots");
  if (args.value("checkpoint-every"))
    options.checkpoint_every = args.integer("checkpoint-every", 0, 0, Args::kInt64Max);
  if (args.value("checkpoint-seconds")) {
    options.checkpoint_seconds = args.number("checkpoint-seconds", 0.0, 0.0);
  }
  if (args.value("checkpoint-keep")) {
    options.checkpoint_keep = static_cast<int>(args.integer("checkpoint-keep", 2, 1));
  }
  return options;
}

/// The picture's options; `picture` is set when one is asked for.
PictureOptions pictureOptions(Args& args, bool& picture) {
  picture = args.flag("picture");
  PictureOptions picture_options;
  if (const auto field = args.value("picture-field")) {
    const auto& known = pictureFields();
    if (std::find(known.begin(), known.end(), *field) == known.end()) {
      throw UsageError(
          cat("--picture-field: unknown field '", *field, "' (known: ", join(known, ", "), ")"));
    }
    picture_options.field = *field;
    picture = true;
  }
  if (args.value("picture-azimuth")) {
    picture_options.azimuth = args.number("picture-azimuth", 0.0);
    picture = true;
  }
  return picture_options;
}

}  // namespace

int runCommand(int argc, char** argv) {
  testPause("startup");  // test hook: signal handlers are in place (main.cpp), no file read yet
  Args args(argc, argv, {"help", "no-snapshots", "quiet", "verbose", "check", "picture"});
  const auto restart = args.value("restart");
  if (args.flag("help") || (args.positional().empty() && !restart)) {
    printUsage();
    return args.flag("help") ? 0 : 2;
  }
  run::RunOptions options = runOptions(args);
  const bool check = args.flag("check");
  bool picture = false;
  const PictureOptions picture_options = pictureOptions(args, picture);
  if (args.flag("quiet")) log::setLevel(log::Level::kWarning);
  if (args.flag("verbose")) log::setLevel(log::Level::kDetail);
  args.rejectUnknown();
  if (args.positional().size() > 1) throw UsageError("polydem run takes one scene file");
  if (options.end_time && !(*options.end_time > 0)) throw UsageError("--end-time must be > 0");
  if (options.kernel && restart) throw UsageError("--kernel cannot change a restarted run");
  if (options.contact_model && restart) {
    throw UsageError("--contact-model cannot change a restarted run");
  }
  options.stop_on_signals = true;
  options.code_version = version();
  options.program = programPath();

  if (restart) {
    std::optional<std::string> scene_file;
    if (!args.positional().empty()) scene_file = args.positional()[0];
    const auto result = run::continueRun(*restart, scene_file, options, MPI_COMM_WORLD);
    if (picture) pictureOf(options, picture_options);
    return check && !result.stopped_early() && !result.all_checks_pass() ? 3 : 0;
  }
  const std::string path = args.positional()[0];
  options.scene_text = scene::readSceneText(path);
  setup::Setup scene = scene::parseScene(options.scene_text, path);
  picture = picture || scene.output.picture;
  // Handed over, not copied: the run's copy is the only one (a list as long as the particles).
  const auto result = run::runScene(std::move(scene), options, MPI_COMM_WORLD);
  if (picture) pictureOf(options, picture_options);
  return check && !result.stopped_early() && !result.all_checks_pass() ? 3 : 0;
}

}  // namespace polydem::app
