// The run-on of a failure to its deposit as the commands run it (`polydem runout`,
// `polydem fos --runout`) and the files they write: runout.json (the result), thickness.csv (the
// thickness map), runout_series.csv (mean displacement and speed against time), thickness.png.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "commands.h"
#include "polydem/run/runout.h"
#include "polydem/setup/setup.h"

namespace polydem::sim {
class Simulation;
}

namespace polydem::app {

/// What the command line sets of a run-on.
struct RunoutOptions {
  std::optional<double> time_cap;                // s; default: the scene's end_time
  std::int64_t check_every = 100;                // steps
  double cell = 0.0;                             // m; 0: the default (run/runout.h)
  std::optional<std::int64_t> checkpoint_every;  // steps; default: [checkpoint] every_steps
};

/// The options --<prefix>time-cap (or --<prefix>time), --<prefix>check-every, --<prefix>cell,
/// --<prefix>checkpoint-every (prefix "" for polydem runout, "runout-" for polydem fos).
RunoutOptions runoutOptions(Args& args, const std::string& prefix);

/// The settings of a run-on of `scene` into `dir` (UsageError without a time cap).
run::RunoutSettings runoutSettings(const setup::Setup& scene, const RunoutOptions& options,
                                   const std::string& dir);

/// The strengths and damping a run-on of `scene` uses, in words: the scene's own (per material:
/// friction angle, cohesion, local and normal damping; its [[interaction]]s and [[joint]]s as
/// written), not the fos trials' reduced strengths and static local damping.
std::string runOnDynamics(const setup::Setup& scene);

/// Continues the failing state of `failing` (a fos trial's simulation, at reduced strength and
/// the static solution's damping) with `scene` as written: its strengths and damping (collective).
run::RunoutResult runOutFrom(sim::Simulation& failing, const setup::Setup& scene,
                             const run::RunoutSettings& settings);

/// runout.json's content.
nlohmann::json runoutJson(const run::RunoutResult& r, const std::string& resume_command,
                          const std::string& picture);

/// Writes runout.json, thickness.csv, runout_series.csv (appended to the rows before this part
/// when continued) and thickness.png into `dir`; returns runout.json's content. Rank 0 only.
nlohmann::json writeRunoutFiles(const std::string& dir, const run::RunoutResult& r,
                                const std::string& resume_command);

/// `polydem fos --runout`: the run-on's files into FOS_DIR/runout, its figures into
/// FOS_DIR/fos.json under "runout", and its line on the console. Rank 0 only.
void addRunout(const std::string& fos_dir, const run::RunoutResult& r, int ranks,
               const std::string& dynamics);

/// One line for the console.
std::string runoutLine(const run::RunoutResult& r, const std::string& dir);

}  // namespace polydem::app
