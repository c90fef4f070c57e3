#include "polydem/output/summary_json.h"

#include <cmath>

#include "polydem/core/error.h"
#include "polydem/core/strings.h"
#include "polydem/output/output_file.h"

namespace polydem::output {

namespace {

nlohmann::json number(double v) {
  return std::isfinite(v) ? nlohmann::json(v) : nullptr;
}

}  // namespace

bool checkPasses(std::string_view compare, double value, double expected, double tolerance) {
  if (compare == "report") return true;
  const double error = std::abs(value - expected);
  if (compare == "abs") return error <= tolerance;
  if (compare == "rel") return error <= tolerance * std::abs(expected);
  if (compare == "max") return value <= expected;
  if (compare == "min") return value >= expected;
  throw Error(cat("check: unknown comparison '", compare, "' (abs, rel, max, min, report)"));
}

nlohmann::json toJson(const CheckResult& check) {
  return {{"name", check.name},
          {"kind", check.kind},
          {"value", number(check.value)},
          {"unit", check.unit},
          {"expected", number(check.expected)},
          {"tolerance", number(check.tolerance)},
          {"compare", check.compare},
          {"pass", check.pass},
          {"reference", check.reference},
          {"note", check.note}};
}

nlohmann::json checksJson(const std::vector<CheckResult>& checks) {
  nlohmann::json out = nlohmann::json::array();
  for (const auto& check : checks) out.push_back(toJson(check));
  return out;
}

nlohmann::json timingJson(const std::vector<TimingPool::Reduced>& rows, std::int64_t steps) {
  nlohmann::json out = nlohmann::json::array();
  for (const auto& r : rows) {
    nlohmann::json row = {{"name", r.name},
                          {"min_s", r.min},
                          {"mean_s", r.mean},
                          {"max_s", r.max},
                          {"count", r.count},
                          {"share", r.share},
                          {"imbalance", number(r.mean > 0 ? r.max / r.mean : 1.0)}};
    if (steps > 0) row["per_step_s"] = r.mean / static_cast<double>(steps);
    out.push_back(std::move(row));
  }
  return out;
}

void writeJsonAtomic(const std::string& path, const nlohmann::json& value) {
  // Invalid UTF-8 (a label from a scene file) is replaced rather than failing the whole summary.
  std::string text = value.dump(2, ' ', false, nlohmann::json::error_handler_t::replace);
  text += '\n';
  writeFileAtomic(path, text);
}

}  // namespace polydem::output
