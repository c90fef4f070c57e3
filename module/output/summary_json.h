// Pieces of summary.json, the machine-readable result of a run: the checks of the scene with their
// verdicts, the timing table reduced over ranks, and an atomic writer (a script polling for
// summary.json never reads half a file).
#pragma once

#include <nlohmann/json.hpp>

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "polydem/core/timing_pool.h"

namespace polydem::output {

/// The outcome of one check of a scene (setup::CheckSpec evaluated on the run).
struct CheckResult {
  std::string name;
  std::string kind;
  double value = 0.0;
  double expected = 0.0;
  double tolerance = 0.0;
  std::string compare = "abs";  // "abs" | "rel" | "max" | "min" | "report" (see CheckSpec)
  bool pass = false;
  std::string reference;  // where `expected` comes from (paper, table, equation)
  std::string note;       // anything a reader needs to judge the value
  std::string unit;       // of value, expected and tolerance: "m", "rad", "1" for a ratio...
};

/// Whether `value` meets `expected` under `compare`:
///   abs: |value - expected| <= tolerance     rel: |value - expected| <= tolerance |expected|
///   max: value <= expected                   min: value >= expected
///   report: always true (recorded only).
/// A NaN value never passes (except "report"). Throws polydem::Error on an unknown `compare`.
bool checkPasses(std::string_view compare, double value, double expected, double tolerance);

/// {name, kind, value, unit, expected, tolerance, compare, pass, reference, note}; non-finite
/// numbers become null (JSON has no NaN).
nlohmann::json toJson(const CheckResult& check);
/// The "checks" array.
nlohmann::json checksJson(const std::vector<CheckResult>& checks);

/// The "timing" array: one object per timer, {name, min_s, mean_s, max_s, count, share,
/// imbalance = max/mean, and per_step_s = mean/steps when steps > 0}.
nlohmann::json timingJson(const std::vector<TimingPool::Reduced>& rows, std::int64_t steps);

/// Writes `value` as indented JSON (two spaces, final newline) to `path` via a temporary file and
/// a rename. Throws polydem::Error naming the path. Not collective: call it on one rank.
void writeJsonAtomic(const std::string& path, const nlohmann::json& value);

}  // namespace polydem::output
