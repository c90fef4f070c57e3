// polydem fos SCENE --out DIR: the factor of safety of a scene by strength reduction
// (run/fos.h), its trials spread over groups of the launched ranks.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <string_view>

#include "commands.h"
#include "fos_files.h"
#include "picture.h"
#include "polydem/contact/contact.h"
#include "polydem/core/error.h"
#include "polydem/core/logging.h"
#include "polydem/core/mpi_env.h"
#include "polydem/core/strings.h"
#include "polydem/output/output_file.h"
#include "polydem/output/output_lock.h"
#include "polydem/particles/material.h"
#include "polydem/run/fos.h"
#include "polydem/run/fos_mechanism.h"
#include "polydem/scene/scene_reader.h"
#include "polydem/sim/simulation.h"
#include "runout_files.h"

namespace polydem::app {

namespace {

void fosUsage() {
  std::printf(
      "usage: [mpirun -n N] polydem fos SCENE.toml --out DIR [options]\n"
      "       [mpirun -n N] polydem fos --resume DIR [--ranks-per-trial K] [--quiet]\n"
      "Factor of safety by strength reduction: tan(friction angle) and cohesion of the scene's\n"
      "[fos] joints and interactions (default: every joint and material pair) are divided by F.\n"
      "Each trial at F is a static solution (local damping 0.8 unless [fos] local_damping\n"
      "says otherwise): stable\n"
      "when the force ratio and the blocks' speeds have decayed, failed when their speeds do not\n"
      "decay over a window while they keep moving, extended up to time_cap when undecided. F is\n"
      "bisected on decided trials to the resolution; the N ranks run N / ranks-per-trial trials\n"
      "side by side. SIGTERM, SIGUSR1 or SIGINT end the running trials after their step and\n"
      "write fos.json with the trials so far (\"complete\": false); --resume DIR continues.\n"
      "  --ranks-per-trial K   ranks of each trial (default 1; must divide N)\n"
      "  --resolution R        width of the final bracket in F (overrides [fos] resolution)\n"
      "  --f-min A, --f-max B  the range searched (overrides [fos] f_min, f_max)\n"
      "  --max-time T          trial length in simulated seconds (overrides [fos] max_time)\n"
      "  --kernel NAME         another contact kernel\n"
      "  --contact-model M     sub-contacts (default) or point (the scene's otherwise)\n"
      "  --resume DIR          continue the search a signal stopped (DIR/fos.json)\n"
      "  --runout              run the mechanism's failing state on at the scene's own strengths\n"
      "                        and damping until at rest: DIR/runout/ (polydem runout --help)\n"
      "  --runout-time T       the run-on's time cap, s (default: the scene's end_time)\n"
      "  --quiet               only the result, warnings and errors\n"
      "  --realizations N      the probability of failure over N realizations of a scene with\n"
      "                        [[random]] inputs (polydem fos --realizations --help)\n"
      "writes DIR/fos.json (factor_of_safety, each reduced joint's and pair's critical strength,\n"
      "the governing one, the mechanism, bracket, criterion, every trial's F, outcome,\n"
      "displacement and time), DIR/fos_trials.csv, DIR/fos.svg (mean displacement against time\n"
      "per trial) and DIR/mechanism/ (the failed trial just above F: snapshots, blocks.csv,\n"
      "frames.png). Settings: docs/scene-format.md, [fos].\n");
}

// The scene and its settings as the stopped search in DIR/fos.json ran them; refuses a scene
// file that changed since.
setup::Setup resumedScene(const FosRun& run, const std::string& dir) {
  if (run.complete) {
    throw UsageError(dir + "/fos.json is complete: there is nothing to resume");
  }
  setup::Setup scene = scene::readScene(run.scene_path);
  if (const std::string now = sceneHash(scene.text); now != run.scene_hash) {
    throw InputError(run.scene_path, 0,
                     cat("the scene file changed since the trials in ", dir,
                         "/fos.json were run (hash ", run.scene_hash, ", now ", now,
                         "): they would not be this scene's; run polydem fos on it afresh"));
  }
  setup::FosSpec& f = scene.fos;
  f.f_min = run.f_min;
  f.f_max = run.f_max;
  f.resolution = run.resolution;
  f.max_time = run.max_time;
  scene.kernel = run.kernel;
  scene.contact_model = run.contact_model;
  return scene;
}

// The scene with the command line's settings over its [fos] and [simulation].
// A factor of safety is a static measure: an acceleration record would shake every trial.
void refuseRecord(const setup::Setup& scene) {
  if (scene.seismic.record_time.empty()) return;
  throw InputError(scene.file, scene.seismic.line,
                   "[seismic] record: polydem fos finds a static factor of safety and cannot run "
                   "with an acceleration record; give the pseudo-static kh (and kv) instead, or "
                   "run the record with polydem run");
}

setup::Setup sceneFromCommandLine(Args& args) {
  const auto resolution = args.value("resolution");
  const auto f_min = args.value("f-min");
  const auto f_max = args.value("f-max");
  const auto max_time = args.value("max-time");
  const auto kernel = args.value("kernel");
  const auto contact_model = args.value("contact-model");
  setup::Setup scene = scene::readScene(args.positional()[0]);
  refuseRecord(scene);
  setup::FosSpec& f = scene.fos;
  if (resolution) f.resolution = args.number("resolution", 0.0);
  if (f_min) f.f_min = args.number("f-min", 0.0);
  if (f_max) f.f_max = args.number("f-max", 0.0);
  if (max_time) f.max_time = args.number("max-time", 0.0);
  args.rejectUnknown();
  if (!(f.resolution > 0)) throw UsageError("--resolution must be > 0");
  if (!(f.f_min > 0) || !(f.f_max > f.f_min)) throw UsageError("need 0 < --f-min < --f-max");
  if (f.max_time && !(*f.max_time > 0)) throw UsageError("--max-time must be > 0");
  if (kernel) {
    contact::makeKernel(*kernel);  // throws with the list of known kernels
    scene.kernel = *kernel;
  }
  if (contact_model) {
    if (const auto e = setup::unknownContactModel(*contact_model); !e.empty()) throw UsageError(e);
    scene.contact_model = *contact_model;
  }
  return scene;
}

void printResult(const setup::Setup& scene, const run::FosResult& result) {
  const auto factor = result.factor();
  if (!result.complete) {
    std::printf("search %s; bracket so far: stable at F = %s, failed at F = %s\n",
                result.note.c_str(), result.stable ? num(*result.stable).c_str() : "(none)",
                result.failed ? num(*result.failed).c_str() : "(none)");
    return;
  }
  if (!factor) {
    std::printf("factor of safety not bracketed: %s\n", result.note.c_str());
    return;
  }
  std::printf(
      "factor of safety %s (stable at F = %s, failed at F = %s, decided trials; "
      "resolution %s)\n",
      num(*factor).c_str(), num(*result.stable).c_str(), num(*result.failed).c_str(),
      num(result.resolution).c_str());
  for (const std::string& line : criticalStrengthLines(scene, *factor)) {
    std::printf("critical strength of %s\n", line.c_str());
  }
  if (!result.note.empty()) std::printf("note: %s\n", result.note.c_str());
}

void printMechanism(const run::FosMechanism& m) {
  std::printf(
      "mechanism: %s (failed trial at F = %s; blocks moved up to %s m in the %s s after "
      "its decision; %s)\n",
      m.summary.c_str(), num(m.factor).c_str(), num(m.max_reach).c_str(),
      num(m.time - m.decided_time).c_str(), m.dir.c_str());
}

// The mechanism of the smallest failed trial, when the search found one (collective).
std::optional<run::FosMechanism> mechanismOf(
    const setup::Setup& scene, const run::FosCriterion& criterion, const run::FosResult& result,
    const std::string& out, const std::function<void(sim::Simulation&)>& then = nullptr) {
  if (!result.complete || !result.failed) return std::nullopt;
  const auto failed = std::find_if(result.trials.begin(), result.trials.end(),
                                   [&](const auto& t) { return t.factor == *result.failed; });
  if (failed == result.trials.end()) return std::nullopt;
  log::info(cat("mechanism: the failed trial at F = ", num(failed->factor),
                " again, with snapshots, into ", out, "/mechanism"));
  const log::Level level = log::level();
  log::setLevel(std::min(level, log::Level::kWarning));  // no run chatter from the trial
  run::FosMechanism m =
      run::runFosMechanism(scene, *failed, criterion, out + "/mechanism", MPI_COMM_WORLD, then);
  log::setLevel(level);
  if (!m.same_bits) {
    log::warning(cat("mechanism: the rerun of the trial at F = ", num(m.factor),
                     " did not reach the search's state at its decision"));
  }
  return m;
}

// Where a search writes, its scene and, for --resume, the stopped search it continues.
struct FosInputs {
  std::string out;
  setup::Setup scene;
  std::optional<FosRun> prior;
};

FosInputs fosInputs(Args& args, const std::optional<std::string>& resume) {
  FosInputs in;
  if (resume) {
    in.out = *resume;
    if (const auto o = args.value("out"); o && *o != in.out) {
      throw UsageError("--resume continues in its own directory: leave out --out");
    }
    args.rejectUnknown();
    in.prior = readFosRun(in.out);
    in.scene = resumedScene(*in.prior, in.out);
  } else {
    in.out = args.value("out", "");
    if (in.out.empty()) throw UsageError("polydem fos needs --out DIR");
    in.scene = sceneFromCommandLine(args);
  }
  return in;
}

// The search's first lines: what it searches, with what criterion, and how a continued search
// differs from an uninterrupted one.
void logFosStart(const setup::Setup& scene, const run::FosCriterion& criterion,
                 const std::optional<FosRun>& prior, const std::string& out, int groups,
                 long long per_trial) {
  if (prior && prior->result.groups != groups) {
    log::warning(
        cat("the stopped search ran ", prior->result.groups, " trials at a time, this one ", groups,
            ": the factors tried from here differ from those of an uninterrupted "
            "search (the same factor of safety within the resolution, not the same bits)"));
  }
  const setup::FosSpec& f = scene.fos;
  log::info(cat("fos: ", scene.id, " (", scene.file, "), kernel ", scene.kernel, ", contact model ",
                scene.contact_model, "; F in [", num(f.f_min), ", ", num(f.f_max), "] to ",
                num(f.resolution), "; ", groups, " trial(s) at a time on ", per_trial,
                " rank(s) each", prior ? cat("; continuing ", out, "/fos.json") : std::string()));
  log::info("criterion: " + criterion.describe());
}

// Rank 0 prints the result and writes the files; a failure (a full disk) is agreed, so that every
// rank ends with the same message and status 1 instead of one rank aborting the others.
void writeFosResults(const setup::Setup& scene, const run::FosCriterion& criterion,
                     const run::FosResult& result, const std::string& out,
                     const std::string& resume_command,
                     const std::optional<run::FosMechanism>& mechanism,
                     const std::optional<run::RunoutResult>& run_on) {
  std::string error;
  if (mpi::rank() == 0) {
    printResult(scene, result);
    std::string picture;
    if (mechanism) {
      printMechanism(*mechanism);
      // The failing blocks coloured by how far they moved, seen from the slope's face.
      PictureOptions view;
      view.field = "displacement";
      picture = renderPicture(mechanism->dir, view);
    }
    try {
      writeFosFiles(out, scene, criterion, result, resume_command,
                    mechanism ? &*mechanism : nullptr, picture);
      if (run_on) addRunout(out, *run_on, mpi::size(), runOnDynamics(scene));
    } catch (const Error& e) {
      error = e.what();
    }
  }
  output::throwIfAnyRankFailed(error, MPI_COMM_WORLD);
  if (mpi::rank() == 0) {
    log::info("wrote " + out + "/fos.json, fos_trials.csv, fos.svg" +
              (mechanism ? ", mechanism/ (snapshots, series.csv, blocks.csv, frames.png)" : ""));
    if (!result.complete) {
      // Printed whatever the log level: the one line a stopped job must leave.
      std::printf("to continue: %s\n", resume_command.c_str());
    }
  }
}

}  // namespace

int fosCommand(int argc, char** argv) {
  for (int i = 1; i < argc; ++i) {  // a study of realizations (fos_realizations.cpp)
    if (std::string_view(argv[i]).starts_with("--realizations")) {
      return fosRealizationsCommand(argc, argv);
    }
  }
  Args args(argc, argv, {"help", "quiet", "runout"});
  const auto resume = args.value("resume");
  if (args.flag("help") || args.positional().size() != (resume ? 0u : 1u)) {
    fosUsage();
    return args.flag("help") ? 0 : 2;
  }
  const long long per_trial = args.integer("ranks-per-trial", 1, 1);
  const bool quiet = args.flag("quiet");
  const bool runout = args.flag("runout");
  const RunoutOptions runout_options = runoutOptions(args, "runout-");
  const FosInputs in = fosInputs(args, resume);
  const std::string& out = in.out;
  const setup::Setup& scene = in.scene;
  const std::optional<FosRun>& prior = in.prior;
  const int ranks = mpi::size();
  if (per_trial < 1 || ranks % per_trial != 0) {
    throw UsageError(cat("--ranks-per-trial ", per_trial, " must divide the ", ranks, " ranks"));
  }
  if (quiet) log::setLevel(log::Level::kWarning);
  const run::FosCriterion criterion = run::fosCriterion(scene);
  std::optional<run::RunoutSettings> runout_settings;
  if (runout) runout_settings = runoutSettings(scene, runout_options, out + "/runout");
  // One search per folder, as for polydem run: a second one into DIR is refused on every rank.
  const output::OutputLock lock(out, MPI_COMM_WORLD);
  const int groups = ranks / static_cast<int>(per_trial);
  logFosStart(scene, criterion, prior, out, groups, per_trial);
  const run::FosResult result = run::findFactorOfSafety(scene, criterion, groups, MPI_COMM_WORLD,
                                                        prior ? &prior->result : nullptr);
  const std::string resume_command =
      result.complete ? std::string()
                      : cat("mpirun -n ", ranks, " ", programPath(), " fos --resume ", out,
                            per_trial != 1 ? cat(" --ranks-per-trial ", per_trial) : "");
  // With --runout, the mechanism's rerun goes on from its failing state to rest.
  std::optional<run::RunoutResult> run_on;
  std::function<void(sim::Simulation&)> then;
  if (runout_settings) {
    then = [&](sim::Simulation& failing) {
      log::info(
          cat("runout: the failing state on into ", out, "/runout, with ", runOnDynamics(scene)));
      run_on = runOutFrom(failing, scene, *runout_settings);
    };
  }
  const std::optional<run::FosMechanism> mechanism =
      mechanismOf(scene, criterion, result, out, then);
  writeFosResults(scene, criterion, result, out, resume_command, mechanism, run_on);
  return 0;
}

}  // namespace polydem::app
