#include "realization_files.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "fos_files.h"
#include "polydem/core/error.h"
#include "polydem/core/state_hash.h"
#include "polydem/core/strings.h"
#include "polydem/output/output_file.h"

namespace polydem::app {

namespace {

using nlohmann::json;

const std::vector<std::string> kLeading = {"realization", "seed"};
const std::vector<std::string> kTrailing = {
    "outcome", "factor_of_safety", "stable",       "failed", "f_min",       "f_max",
    "fails",   "trials",           "wall_seconds", "group",  "trial_hashes"};

std::vector<std::string> header(const scene::Study& study) {
  std::vector<std::string> h = kLeading;
  for (const std::string& c : study.columns()) h.push_back(c);
  h.insert(h.end(), kTrailing.begin(), kTrailing.end());
  return h;
}

std::vector<std::string> split(const std::string& line, char sep) {
  std::vector<std::string> out;
  std::stringstream s(line);
  for (std::string cell; std::getline(s, cell, sep);) out.push_back(cell);
  if (!line.empty() && line.back() == sep) out.emplace_back();
  return out;
}

std::string optionalText(const std::optional<double>& v) {
  return v ? shortest(*v) : "";
}

std::optional<double> optionalNumber(const std::string& s) {
  if (s.empty()) return std::nullopt;
  return std::stod(s);
}

json optionalJson(const std::optional<double>& v) {
  return v ? json(*v) : json();
}

}  // namespace

StudySummary summarize(const std::vector<run::RealizationResult>& results) {
  StudySummary s;
  s.count = results.size();
  double sum = 0.0;
  for (const auto& r : results) {
    if (r.factor) {
      ++s.resolved;
      sum += *r.factor;
    }
    if (const auto f = r.fails()) {
      ++s.known;
      s.failures += *f;
    }
  }
  if (s.resolved > 0) {
    s.mean = sum / static_cast<double>(s.resolved);
    double squares = 0.0;
    for (const auto& r : results) {
      if (r.factor) squares += (*r.factor - *s.mean) * (*r.factor - *s.mean);
    }
    if (s.resolved > 1) s.sd = std::sqrt(squares / static_cast<double>(s.resolved - 1));
  }
  if (s.known > 0) {
    const double n = static_cast<double>(s.known);
    s.pof = static_cast<double>(s.failures) / n;
    s.pof_se = std::sqrt(*s.pof * (1.0 - *s.pof) / n);
  }
  return s;
}

std::vector<run::RealizationResult> readRealizationsCsv(const std::string& dir,
                                                        const scene::Study& study) {
  const std::string path = dir + "/realizations.csv";
  std::vector<run::RealizationResult> out;
  if (!std::filesystem::exists(path)) return out;
  std::ifstream in(path);
  if (!in) throw InputError(path, 0, "cannot read it");
  const std::vector<std::string> expected = header(study);
  std::string line;
  std::getline(in, line);
  if (split(line, ',') != expected) {
    throw InputError(path, 1,
                     "its columns are not those of this scene's [[random]] entries: the study in " +
                         dir + " drew other inputs; run this one into another folder");
  }
  const std::size_t inputs = study.columns().size();
  for (int number = 2; std::getline(in, line); ++number) {
    const std::vector<std::string> c = split(line, ',');
    if (c.size() != expected.size()) {
      throw InputError(path, number, cat("expected ", expected.size(), " cells, got ", c.size()));
    }
    try {
      run::RealizationResult r;
      r.index = std::stoll(c[0]);
      r.seed = std::stoull(c[1], nullptr, 16);
      for (std::size_t k = 0; k < inputs; ++k) r.values.push_back(std::stod(c[2 + k]));
      std::size_t i = 2 + inputs;
      r.outcome = c[i++];
      r.factor = optionalNumber(c[i++]);
      r.stable = optionalNumber(c[i++]);
      r.failed = optionalNumber(c[i++]);
      r.f_min = std::stod(c[i++]);
      r.f_max = std::stod(c[i++]);
      ++i;  // fails: from the rest
      r.trials = std::stoi(c[i++]);
      r.wall_seconds = std::stod(c[i++]);
      r.group = std::stoi(c[i++]);
      for (const std::string& h : split(c[i], ' ')) {
        if (!h.empty()) r.trial_hashes.push_back(std::stoull(h, nullptr, 16));
      }
      out.push_back(r);
    } catch (const std::logic_error&) {
      throw InputError(path, number, "a cell is not a number where one is expected");
    }
  }
  return out;
}

void writeRealizationsCsv(const std::string& dir, const scene::Study& study,
                          const std::vector<run::RealizationResult>& results) {
  std::ostringstream s;
  const std::vector<std::string> h = header(study);
  for (std::size_t k = 0; k < h.size(); ++k) s << (k ? "," : "") << h[k];
  s << "\n";
  for (const auto& r : results) {
    s << r.index << "," << BitHasher::hex(r.seed);
    for (const double v : r.values) s << "," << shortest(v);
    const auto fails = r.fails();
    s << "," << r.outcome << "," << optionalText(r.factor) << "," << optionalText(r.stable) << ","
      << optionalText(r.failed) << "," << shortest(r.f_min) << "," << shortest(r.f_max) << ","
      << (fails ? (*fails ? "1" : "0") : "") << "," << r.trials << "," << shortest(r.wall_seconds)
      << "," << r.group << ",";
    for (std::size_t k = 0; k < r.trial_hashes.size(); ++k) {
      s << (k ? " " : "") << BitHasher::hex(r.trial_hashes[k]);
    }
    s << "\n";
  }
  output::writeFileAtomic(dir + "/realizations.csv", s.str());
}

void writeRealizationsJson(const std::string& dir, const scene::Study& study, std::int64_t asked,
                           bool complete, const StudySummary& s, double wall_seconds,
                           const std::string& command) {
  json inputs = json::array();
  for (const scene::RandomInput& in : study.inputs) {
    json e = {{"parameter", in.parameter}, {"distribution", in.distribution}};
    if (in.distribution == "normal" || in.distribution == "lognormal" ||
        in.distribution == "truncated") {
      e["mean"] = in.mean;
      e["sd"] = in.sd;
    }
    if (in.distribution == "uniform" || in.distribution == "truncated") {
      e["min"] = in.min;
      e["max"] = in.max;
    }
    if (in.distribution == "fisher") e["k"] = in.k;
    inputs.push_back(e);
  }
  const json j = {
      {"scene_path", std::filesystem::absolute(study.file).lexically_normal().string()},
      {"scene_hash", sceneHash(study.text)},
      {"seed", study.seed},
      {"realizations_asked", asked},
      {"complete", complete},
      {"inputs", inputs},
      {"count", s.count},
      {"resolved", s.resolved},
      {"known", s.known},
      {"failures", s.failures},
      {"mean_factor_of_safety", optionalJson(s.mean)},
      {"sd_factor_of_safety", optionalJson(s.sd)},
      {"probability_of_failure", optionalJson(s.pof)},
      {"probability_of_failure_se", optionalJson(s.pof_se)},
      {"wall_seconds", wall_seconds},
      {"command", command},
  };
  output::writeFileAtomic(dir + "/realizations.json", j.dump(2) + "\n");
}

std::optional<std::pair<std::string, std::uint64_t>> previousStudy(const std::string& dir) {
  const std::string path = dir + "/realizations.json";
  if (!std::filesystem::exists(path)) return std::nullopt;
  std::ifstream in(path);
  try {
    const json j = json::parse(in);
    return std::pair{j.at("scene_hash").get<std::string>(), j.at("seed").get<std::uint64_t>()};
  } catch (const json::exception& e) {
    throw InputError(path, 0, cat("cannot read the study it describes: ", e.what()));
  }
}

}  // namespace polydem::app
