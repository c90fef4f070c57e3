// polydem fos SCENE --realizations N --out DIR: the probability of failure of a scene with random
// inputs ([[random]], scene/scene_random.h): the factor of safety of N realizations
// (run/realizations.h), side by side over groups of the launched ranks.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <set>

#include "commands.h"
#include "fos_files.h"
#include "picture.h"
#include "polydem/core/error.h"
#include "polydem/core/logging.h"
#include "polydem/core/mpi_env.h"
#include "polydem/core/strings.h"
#include "polydem/output/output_file.h"
#include "polydem/output/output_lock.h"
#include "polydem/run/realizations.h"
#include "realization_files.h"

namespace polydem::app {

namespace {

void realizationsUsage() {
  std::printf(
      "usage: [mpirun -n N] polydem fos SCENE.toml --realizations COUNT --out DIR [options]\n"
      "Probability of failure: the factor of safety of COUNT realizations of a scene whose\n"
      "[[random]] entries draw strengths, orientations, spacings, the water level or kh from\n"
      "distributions (docs/scene-format.md, \"Random inputs\"). Realization i has its own seed\n"
      "from [realizations] seed and i; each one's F is the fos search of its scene, the same\n"
      "bits as polydem fos on DIR/scenes/realization-i.toml alone. The ranks run\n"
      "N / ranks-per-realization realizations side by side. SIGTERM, SIGUSR1 or SIGINT stop it\n"
      "after the running searches' step; the same command again continues it (the finished\n"
      "realizations in DIR/realizations.csv are kept; a larger COUNT extends a study).\n"
      "  --ranks-per-realization K   ranks of each realization's search (default 1)\n"
      "  --quiet                     only the result, warnings and errors\n"
      "writes DIR/realizations.csv (every realization's seed, inputs, F, outcome, trial hashes),\n"
      "DIR/realizations.json (mean and sd of F, P(F < 1) and its standard error, counts),\n"
      "DIR/realizations.png (histogram and CDF of F) and DIR/scenes/realization-NNNN.toml.\n");
}

std::string sceneFileOf(const std::string& dir, std::int64_t index) {
  char name[64];
  std::snprintf(name, sizeof name, "/scenes/realization-%04lld.toml",
                static_cast<long long>(index));
  return dir + name;
}

std::string resultLine(const run::RealizationResult& r, std::size_t done, std::int64_t asked) {
  return cat("realization ", r.index, " (", done, " of ", asked,
             "): ", r.factor ? cat("F = ", num(*r.factor)) : r.outcome, ", ", r.trials, " trials, ",
             num(r.wall_seconds), " s wall, group ", r.group);
}

void printSummary(const StudySummary& s, std::int64_t asked, bool complete) {
  std::printf("%s: %zu of %lld realizations, %zu with F resolved", complete ? "study" : "stopped",
              s.count, static_cast<long long>(asked), s.resolved);
  if (s.mean) std::printf("; mean F %s", num(*s.mean).c_str());
  if (s.sd) std::printf(", sd %s", num(*s.sd).c_str());
  if (s.pof) {
    std::printf("; P(F < 1) = %s +- %s (%zu of %zu)", num(*s.pof).c_str(), num(*s.pof_se).c_str(),
                s.failures, s.known);
  }
  std::printf("\n");
}

// The study so far in DIR: the finished realizations of this scene and seed. A folder that holds
// another scene's study is refused.
std::vector<run::RealizationResult> previousResults(const std::string& out,
                                                    const scene::Study& study) {
  const auto previous = previousStudy(out);
  if (!previous) return {};
  if (previous->first != sceneHash(study.text) || previous->second != study.seed) {
    throw InputError(
        out + "/realizations.json", 0,
        cat("the study in ", out, " ran another scene file or seed (hash ", previous->first,
            ", seed ", previous->second, "; now ", sceneHash(study.text), ", seed ", study.seed,
            "): its realizations are not this scene's; use another --out"));
  }
  return readRealizationsCsv(out, study);
}

// The command that runs (and continues) this study.
std::string studyCommand(const scene::Study& study, long long asked, const std::string& out,
                         long long per, int ranks) {
  std::string command = cat("polydem fos ", study.file, " --realizations ", asked, " --out ", out);
  if (per != 1) command += cat(" --ranks-per-realization ", per);
  if (ranks > 1) command = cat("mpirun -n ", ranks, " ", command);
  return command;
}

}  // namespace

int fosRealizationsCommand(int argc, char** argv) {
  Args args(argc, argv, {"help", "quiet"});
  if (args.flag("help") || args.positional().size() != 1) {
    realizationsUsage();
    return args.flag("help") ? 0 : 2;
  }
  const long long asked = args.integer("realizations", 0, 1, 1000000);
  const long long per = args.integer("ranks-per-realization", 1, 1);
  const bool quiet = args.flag("quiet");
  const std::string out = args.value("out", "");
  args.rejectUnknown();
  if (out.empty()) throw UsageError("polydem fos --realizations needs --out DIR");
  const int ranks = mpi::size();
  if (ranks % per != 0) {
    throw UsageError(cat("--ranks-per-realization ", per, " must divide the ", ranks, " ranks"));
  }
  if (quiet) log::setLevel(log::Level::kWarning);
  const auto start = std::chrono::steady_clock::now();
  const scene::Study study = scene::readStudy(args.positional()[0]);
  const output::OutputLock lock(out, MPI_COMM_WORLD);
  std::vector<run::RealizationResult> done = previousResults(out, study);
  std::set<std::int64_t> finished;
  for (const auto& r : done) finished.insert(r.index);
  std::vector<std::int64_t> todo;
  for (std::int64_t i = 0; i < asked; ++i) {
    if (!finished.count(i)) todo.push_back(i);
  }
  const int groups = ranks / static_cast<int>(per);
  const std::string command = studyCommand(study, asked, out, per, ranks);
  log::info(cat("fos --realizations: ", study.file, ", ", study.inputs.size(),
                " random input(s), seed ", study.seed, "; ", asked, " realizations, ",
                finished.size(), " already in ", out, "/realizations.csv; ", groups,
                " at a time on ", per, " rank(s) each"));
  const auto elapsed = [&start] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  };
  // After every round rank 0 rewrites the state (atomically) and the finished scene files.
  const auto round_done = [&](const std::vector<run::RealizationResult>& round) {
    std::string error;
    if (mpi::rank() == 0) {
      try {
        output::createDirectories(out + "/scenes");
        for (const auto& r : round) {
          output::writeFileAtomic(sceneFileOf(out, r.index),
                                  scene::drawRealization(study, r.index).text);
          done.push_back(r);
          log::info(resultLine(r, done.size(), asked));
        }
        std::sort(done.begin(), done.end(),
                  [](const auto& a, const auto& b) { return a.index < b.index; });
        writeRealizationsCsv(out, study, done);
        writeRealizationsJson(out, study, asked, false, summarize(done), elapsed(), command);
      } catch (const Error& e) {
        error = e.what();
      }
    }
    output::throwIfAnyRankFailed(error, MPI_COMM_WORLD);
  };
  if (mpi::rank() == 0) {
    // The study's identity first: a study stopped before its first round continues too.
    writeRealizationsJson(out, study, asked, false, summarize(done), elapsed(), command);
  }
  const bool complete = run::runRealizations(study, todo, groups, MPI_COMM_WORLD, round_done);
  std::string error;
  if (mpi::rank() == 0) {
    std::vector<run::RealizationResult> asked_for;
    for (const auto& r : done) {
      if (r.index < asked) asked_for.push_back(r);
    }
    const StudySummary s = summarize(asked_for);
    printSummary(s, asked, complete);
    try {
      writeRealizationsCsv(out, study, done);
      writeRealizationsJson(out, study, asked, complete, s, elapsed(), command);
    } catch (const Error& e) {
      error = e.what();
    }
    // The plots once the study is complete (a stop signal may reach the plotting process too).
    if (error.empty() && complete) plotRealizations(out);
    if (error.empty() && !complete) std::printf("to continue: %s\n", command.c_str());
  }
  output::throwIfAnyRankFailed(error, MPI_COMM_WORLD);
  return 0;
}

}  // namespace polydem::app
