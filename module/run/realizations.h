// A probability-of-failure study: the factor of safety of every realization of a scene with
// random inputs (scene/scene_random.h), realizations side by side over groups of the launched
// ranks. Each realization's F is the fos search of its own scene (run/fos.h) on one group, so it
// is the same bits as `polydem fos` on that scene alone, on any rank count. A stop signal ends
// the running searches; the realizations finished by then are kept, and a study continued
// without them runs the rest.
#pragma once

#include <mpi.h>

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "polydem/scene/scene_random.h"

namespace polydem::run {

/// One realization's factor of safety.
struct RealizationResult {
  std::int64_t index = 0;
  std::uint64_t seed = 0;
  std::vector<double> values;  // the drawn inputs, in Study::columns() order
  /// "resolved", "below f_min" (a failed trial at f_min), "above f_max" (a stable trial at
  /// f_max), "not resolved" (undecided trials: the search's note says why) or "invalid" (its
  /// draws give no scene, as when a rock mass cannot be cut so: a warning says why).
  std::string outcome;
  std::optional<double> factor;          // resolved: (stable + failed) / 2
  std::optional<double> stable, failed;  // the bracket
  double f_min = 0.0, f_max = 0.0;
  std::vector<std::uint64_t> trial_hashes;  // state hash of each trial, in search order
  int trials = 0;
  double wall_seconds = 0.0;
  int group = 0;
  /// Whether F < 1: known when resolved, or when a decided trial bounds F on one side of 1 (a
  /// failed trial at F <= 1, a stable one at F >= 1: below f_min, above f_max, or a search that
  /// an undecided trial left unresolved).
  std::optional<bool> fails() const;
};

/// Runs realizations `todo` (indices) of `study`, `groups` at a time on as many groups of the
/// ranks of `comm` (collective; `groups` divides the rank count). After every round of `groups`
/// realizations, `round_done` gets the round's results on every rank (in `todo` order).
/// Returns false when a stop signal ended it (the searches it cut short are dropped, those of the
/// round that finished are kept). A search that throws ends it on every rank with that error.
bool runRealizations(const scene::Study& study, const std::vector<std::int64_t>& todo, int groups,
                     MPI_Comm comm,
                     const std::function<void(const std::vector<RealizationResult>&)>& round_done);

}  // namespace polydem::run
