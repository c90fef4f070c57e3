// The files of `polydem fos SCENE --realizations N --out DIR`: DIR/realizations.csv (every
// finished realization: its seed, drawn inputs, F and outcome; the study's state, rewritten
// atomically after every round, so that a stopped study continues from it),
// DIR/realizations.json (the summary), DIR/scenes/realization-NNNN.toml (each realization's
// scene file, which `polydem fos` runs alone to the same bits) and DIR/realizations.png.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "polydem/run/realizations.h"
#include "polydem/scene/scene_random.h"

namespace polydem::app {

/// The study's figures over the finished realizations.
struct StudySummary {
  std::size_t count = 0;              // finished realizations
  std::size_t resolved = 0;           // with a resolved F (mean, sd are over these)
  std::size_t known = 0;              // whose F < 1 or not is known (P(F < 1) is over these)
  std::size_t failures = 0;           // F < 1
  std::optional<double> mean, sd;     // of F
  std::optional<double> pof, pof_se;  // P(F < 1) and its binomial standard error
};

StudySummary summarize(const std::vector<run::RealizationResult>& results);

/// The finished realizations in DIR/realizations.csv (none if it does not exist). InputError
/// naming the file and line for a file this study did not write (other columns, a bad row).
std::vector<run::RealizationResult> readRealizationsCsv(const std::string& dir,
                                                        const scene::Study& study);

/// Rewrites DIR/realizations.csv atomically with `results` (sorted by index).
void writeRealizationsCsv(const std::string& dir, const scene::Study& study,
                          const std::vector<run::RealizationResult>& results);

/// Writes DIR/realizations.json: the scene, its hash, the seed, the count asked for, whether the
/// study is complete, the summary and the wall time.
void writeRealizationsJson(const std::string& dir, const scene::Study& study, std::int64_t asked,
                           bool complete, const StudySummary& s, double wall_seconds,
                           const std::string& command);

/// The scene hash and seed a previous study in DIR ran, if DIR/realizations.json exists.
std::optional<std::pair<std::string, std::uint64_t>> previousStudy(const std::string& dir);

}  // namespace polydem::app
