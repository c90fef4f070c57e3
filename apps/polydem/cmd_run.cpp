// polydem run SCENE --out DIR: runs a scene file (on as many ranks as mpirun gives).
#include <cstdio>

#include "commands.h"
#include "core/error.h"
#include "core/logging.h"
#include "io/scene_reader.h"
#include "sim/run.h"

namespace polydem::app {

int runCommand(int argc, char** argv) {
  Args args(argc, argv, {"help", "no-snapshots", "quiet", "check"});
  if (args.flag("help") || args.positional().empty()) {
    std::printf(
        "usage: [mpirun -n N] polydem run SCENE.toml --out DIR [options]\n"
        "  --steps N         run N steps (replaces the scene's end condition)\n"
        "  --end-time T      run until simulated time T (replaces the scene's end condition)\n"
        "  --kernel NAME     use another contact kernel (polydem kernels lists them)\n"
        "  --progress N      progress line every N steps (default: every 5 s)\n"
        "  --no-snapshots    do not write ParaView snapshots\n"
        "  --check           exit with status 3 if a check of the scene fails\n"
        "  --quiet           only warnings and errors\n"
        "writes DIR/summary.json, DIR/series.csv and DIR/snapshots.pvd (+ snapshots/)\n");
    return args.flag("help") ? 0 : 2;
  }
  sim::RunOptions options;
  options.out_dir = args.value("out", "");
  if (options.out_dir.empty()) throw UsageError("polydem run needs --out DIR");
  if (const auto v = args.value("steps")) options.steps = args.integer("steps", 0);
  if (const auto v = args.value("end-time")) options.end_time = args.number("end-time", 0.0);
  options.kernel = args.value("kernel");
  options.progress_every = args.integer("progress", 0);
  options.snapshots = !args.flag("no-snapshots");
  const bool check = args.flag("check");
  if (args.flag("quiet")) log::setLevel(log::Level::kWarning);
  args.rejectUnknown();
  if (args.positional().size() != 1) throw UsageError("polydem run takes one scene file");
  if (options.steps && *options.steps <= 0) throw UsageError("--steps must be positive");
  if (options.end_time && !(*options.end_time > 0)) throw UsageError("--end-time must be > 0");

  const io::Scene scene = io::readScene(args.positional()[0]);
  const auto result = sim::runScene(scene, options, MPI_COMM_WORLD);
  return check && !result.all_checks_pass() ? 3 : 0;
}

}  // namespace polydem::app
