// polydem bench kernels: throughput of every contact kernel beside libccd 2.1 on the same pairs,
// one core, median of timed passes; contact-point error on face-face pairs.
#include "bench_kernels.h"

#include <ccd/ccd.h>

#include <algorithm>
#include <cstdio>
#include <ctime>
#include <fstream>
#include <functional>
#include <limits>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "commands.h"
#include "polydem/core/mpi_env.h"
#include "polydem/core/strings.h"

namespace polydem::app {

namespace {

constexpr const char* kCcdGjkEpa = "libccd-gjk-epa";
constexpr const char* kCcdMpr = "libccd-mpr";
// libccd's tolerances are absolute; the defaults (EPA and MPR 1e-4, distance 1e-6) are a tenth
// of the smallest face-face penetration here. For unit-size bodies with penetrations down to
// 1e-5 we set all three to 1e-9 (1e-4 of the smallest depth) and bound the iterations.
constexpr double kCcdTolerance = 1e-9;
constexpr unsigned long kCcdMaxIterations = 1000;

// ---- libccd peer: support over the same world vertices -----------------------------------

void ccdSupport(const void* object, const ccd_vec3_t* dir, ccd_vec3_t* out) {
  const auto& body = *static_cast<const contact::Body*>(object);
  const Vec3 d(dir->v[0], dir->v[1], dir->v[2]);
  std::size_t best = 0;
  double best_value = d.dot(body.vertices[0]);
  for (std::size_t i = 1; i < body.vertices.size(); ++i) {
    const double value = d.dot(body.vertices[i]);
    if (value > best_value) {
      best = i;
      best_value = value;
    }
  }
  for (int k = 0; k < 3; ++k) out->v[k] = body.vertices[best][k];
}

void ccdCentre(const void* object, ccd_vec3_t* out) {
  const Vec3 c = static_cast<const contact::Body*>(object)->centroid();
  for (int k = 0; k < 3; ++k) out->v[k] = c[k];
}

ccd_t ccdSettings() {
  ccd_t ccd;
  CCD_INIT(&ccd);
  ccd.support1 = ccdSupport;
  ccd.support2 = ccdSupport;
  ccd.center1 = ccdCentre;
  ccd.center2 = ccdCentre;
  ccd.max_iterations = kCcdMaxIterations;
  ccd.epa_tolerance = kCcdTolerance;
  ccd.mpr_tolerance = kCcdTolerance;
  ccd.dist_tolerance = kCcdTolerance;
  return ccd;
}

// ---- one resolver per row: resolves pair i and returns the contact point ----------------

using Resolver = std::function<bool(std::size_t, Vec3&, double&)>;

Resolver kernelResolver(const contact::Kernel& kernel, const PairSet& set,
                        std::vector<particles::PairState>& states, bool cold) {
  return [&kernel, &set, &states, cold](std::size_t i, Vec3& point, double& depth) {
    const contact::Contact c = kernel.collide(set.a[i], set.b[i], cold ? nullptr : &states[i]);
    point = c.point;
    depth = c.depth;
    return c.touching;
  };
}

Resolver ccdResolver(bool mpr, const PairSet& set) {
  return [mpr, &set, ccd = ccdSettings()](std::size_t i, Vec3& point, double& depth) {
    ccd_real_t d = 0;
    ccd_vec3_t dir, pos;
    const int rc = mpr ? ccdMPRPenetration(&set.a[i], &set.b[i], &ccd, &d, &dir, &pos)
                       : ccdGJKPenetration(&set.a[i], &set.b[i], &ccd, &d, &dir, &pos);
    point = Vec3(pos.v[0], pos.v[1], pos.v[2]);
    depth = d;
    return rc == 0;
  };
}

// ---- measurement ---------------------------------------------------------------------------

struct Row {
  std::string name;
  std::string set;
  std::string states;  // "warm": each pair keeps its PairState across passes; "cold": none;
                       // "none": a stateless peer (libccd)
  double per_second = 0.0;
  int missed = 0;                                                 // overlapping pairs not found
  double point_error = std::numeric_limits<double>::quiet_NaN();  // mean, face-face only
  double point_error_max = std::numeric_limits<double>::quiet_NaN();
};

double sink = 0.0;  // keeps the timed work observable

/// CPU time of this thread: on a shared machine the time the core was actually ours, so that
/// other processes do not dilute the figures (they still compete for caches and memory).
double threadSeconds() {
  timespec t;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

double pass(const Resolver& resolve, std::size_t n) {
  Vec3 point;
  double depth = 0.0, sum = 0.0;
  const double t0 = threadSeconds();
  for (std::size_t i = 0; i < n; ++i) {
    resolve(i, point, depth);
    sum += depth;
  }
  const double t1 = threadSeconds();
  sink += sum;
  return t1 - t0;
}

/// One row under measurement: its resolver, pair states and timed passes.
struct Measurement {
  Row row;
  const PairSet* set = nullptr;
  std::unique_ptr<std::vector<particles::PairState>> states;
  Resolver resolve;
  int repeats = 1;
  std::vector<double> rates;
};

/// The untimed pass: misses and face-face point errors, and pair states warmed.
void checkRow(Measurement& m) {
  const PairSet& set = *m.set;
  Row& row = m.row;
  Vec3 point;
  double depth = 0.0, sum = 0.0, worst = 0.0;
  for (std::size_t i = 0; i < set.size(); ++i) {
    const bool touching = m.resolve(i, point, depth);
    row.missed += !touching;
    if (!set.exact_point.empty() && touching) {
      const double e = (point - set.exact_point[i]).norm();  // unit cubes: relative to the size
      sum += e;
      worst = std::max(worst, e);
    }
  }
  if (!set.exact_point.empty() && row.missed < static_cast<int>(set.size())) {
    row.point_error = sum / static_cast<double>(set.size() - row.missed);
    row.point_error_max = worst;
  }
}

/// Each row gets `passes` timed passes of about seconds / passes each, taken round-robin over the
/// rows so that a slow spell of the machine hits every row alike; its figure is the median.
void measureAll(std::vector<Measurement>& all, double seconds, int passes) {
  for (Measurement& m : all) {
    const double once = std::max(pass(m.resolve, m.set->size()), 1e-9);
    m.repeats = std::max(1, static_cast<int>(seconds / passes / once));
  }
  for (int p = 0; p < passes; ++p) {
    for (Measurement& m : all) {
      double t = 0.0;
      for (int r = 0; r < m.repeats; ++r) t += pass(m.resolve, m.set->size());
      m.rates.push_back(static_cast<double>(m.set->size()) * m.repeats / t);
    }
  }
  for (Measurement& m : all) {
    std::sort(m.rates.begin(), m.rates.end());
    m.row.per_second = m.rates[m.rates.size() / 2];
  }
}

std::string rate(double per_second) {
  char buf[32];
  if (per_second >= 1e6) {
    std::snprintf(buf, sizeof buf, "%.2f M/s", per_second / 1e6);
  } else {
    std::snprintf(buf, sizeof buf, "%.1f k/s", per_second / 1e3);
  }
  return buf;
}

/// One line per kernel and pair-state mode: the warm and the cold line of a kernel side by side,
/// so that the figures against the stateless libccd are read for both.
void printTable(const std::vector<Row>& rows, const std::vector<std::string>& sets) {
  std::printf("\n%-20s %-6s", "kernel", "states");
  for (const auto& s : sets) std::printf(" %24s", s.c_str());
  std::printf("   face-face point error mean / max\n");
  std::vector<std::pair<std::string, std::string>> lines;
  for (const Row& r : rows) {
    const std::pair line{r.name, r.states};
    if (std::find(lines.begin(), lines.end(), line) == lines.end()) lines.push_back(line);
  }
  for (const auto& [name, states] : lines) {
    std::printf("%-20s %-6s", name.c_str(), states.c_str());
    const Row* ff = nullptr;
    for (const auto& s : sets) {
      const Row* row = nullptr;
      const Row* peer = nullptr;
      for (const Row& r : rows) {
        if (r.set == s && r.name == name && r.states == states) row = &r;
        if (r.set == s && r.name == kCcdGjkEpa) peer = &r;
      }
      if (row == nullptr) {
        std::printf(" %24s", "-");
        continue;
      }
      if (s == "face-face") ff = row;
      char ratio[32] = "-";
      if (peer != nullptr)
        std::snprintf(ratio, sizeof ratio, "%.2f", row->per_second / peer->per_second);
      const std::string cell = cat(rate(row->per_second), " (x", ratio, ")",
                                   row->missed > 0 ? cat(" miss ", row->missed) : std::string());
      std::printf(" %24s", cell.c_str());
    }
    if (ff != nullptr && !std::isnan(ff->point_error)) {
      std::printf("   %.2e / %.2e", ff->point_error, ff->point_error_max);
    }
    std::printf("\n");
  }
}

void printHelp() {
  std::printf(
      "usage: polydem bench kernels [--pairs N] [--seconds S] [--passes P] [--kernels a,b]\n"
      "                             [--sets a,b] [--cold] [--json FILE]\n"
      "  Contact resolutions per second on one core for each kernel (default: every registered\n"
      "  one, %s and %s) on N pre-generated overlapping pairs (default 1000)\n"
      "  of each set: face-face cube pairs, randomly oriented cube pairs, random polyhedra of\n"
      "  8-40 vertices (--sets: some of face-face, random-cubes, random-polyhedra).\n"
      "  A figure is the median of P round-robin passes (default 7) over S\n"
      "  seconds (default 1) of this thread's CPU time per row. Ratios are against %s,\n"
      "  which always runs. Each kernel is measured warm (every pair keeps its PairState across\n"
      "  passes, as in a static scene step after step) and cold (no state: a pair's first\n"
      "  contact), side by side; --warm or --cold measures one of them only. libccd keeps no\n"
      "  state. --json writes one record per kernel, set and state mode.\n",
      kCcdGjkEpa, kCcdMpr, kCcdGjkEpa);
}

struct Options {
  int pairs = 1000;
  double seconds = 1.0;
  int passes = 7;
  bool only_cold = false, only_warm = false;
  std::vector<bool> modes;  // cold?
  std::optional<std::string> json_path;
  std::vector<std::string> names;      // kernels, then the libccd peers
  std::vector<std::string> set_names;  // pair sets
};

// The comma-separated list of --`option`, each one of `known` (else a UsageError naming the
// unknown `what`), or `known` itself when the option is not given.
std::vector<std::string> chosenNames(Args& args, const char* option, const char* what,
                                     const std::vector<std::string>& known) {
  const auto chosen = args.value(option);
  if (!chosen) return known;
  const auto wanted = split(*chosen, ',');
  for (const auto& w : wanted) {
    if (std::find(known.begin(), known.end(), w) == known.end()) {
      throw UsageError(
          cat("--", option, ": unknown ", what, " '", w, "'; known: ", join(known, ", ")));
    }
  }
  return wanted;
}

Options parseOptions(Args& args) {
  Options o;
  o.pairs = static_cast<int>(args.integer("pairs", 1000, 1));
  o.seconds = args.number("seconds", 1.0);
  o.passes = static_cast<int>(args.integer("passes", 7, 1));
  o.only_cold = args.flag("cold");
  o.only_warm = args.flag("warm");
  if (o.only_cold && o.only_warm) throw UsageError("--warm and --cold exclude each other");
  if (!o.only_cold) o.modes.push_back(false);
  if (!o.only_warm) o.modes.push_back(true);
  o.json_path = args.value("json");
  std::vector<std::string> names = contact::kernelNames();
  names.push_back(kCcdGjkEpa);
  names.push_back(kCcdMpr);
  o.names = chosenNames(args, "kernels", "kernel", names);
  // The ratios' peer is always measured in the same run.
  if (std::find(o.names.begin(), o.names.end(), kCcdGjkEpa) == o.names.end()) {
    o.names.push_back(kCcdGjkEpa);
  }
  o.set_names = chosenNames(args, "sets", "set", {"face-face", "random-cubes", "random-polyhedra"});
  args.rejectUnknown();
  if (!(o.seconds > 0.0)) throw UsageError("--seconds must be > 0");
  return o;
}

// The pair sets, each from its fixed seed: the same pairs whichever sets are chosen.
std::vector<PairSet> makeSets(const std::vector<std::string>& set_names, int pairs) {
  std::vector<PairSet> sets;
  for (const auto& name : set_names) {
    if (name == "face-face") sets.push_back(faceFacePairs(pairs, 101));
    if (name == "random-cubes") sets.push_back(randomCubePairs(pairs, 202));
    if (name == "random-polyhedra") sets.push_back(randomPolyhedronPairs(pairs, 303));
  }
  return sets;
}

// One checked Measurement per kernel, state mode and set (libccd: no state mode); `kernels`
// keeps the kernels the resolvers call.
std::vector<Measurement> prepareMeasurements(
    const Options& o, const std::vector<PairSet>& sets,
    std::vector<std::unique_ptr<contact::Kernel>>& kernels) {
  std::vector<Measurement> all;
  for (const auto& name : o.names) {
    if (name != kCcdGjkEpa && name != kCcdMpr) kernels.push_back(contact::makeKernel(name));
    const contact::Kernel* kernel =
        (name != kCcdGjkEpa && name != kCcdMpr) ? kernels.back().get() : nullptr;
    for (const bool cold : kernel ? o.modes : std::vector<bool>{false}) {
      for (const PairSet& set : sets) {
        Measurement m;
        m.row.name = name;
        m.row.set = set.name;
        m.row.states = kernel ? (cold ? "cold" : "warm") : "none";
        m.set = &set;
        m.states = std::make_unique<std::vector<particles::PairState>>(set.size());
        m.resolve = kernel ? kernelResolver(*kernel, set, *m.states, cold)
                           : ccdResolver(name == kCcdMpr, set);
        checkRow(m);
        all.push_back(std::move(m));
      }
    }
  }
  return all;
}

void writeJson(const std::vector<Row>& rows, const std::string& path) {
  nlohmann::json out = nlohmann::json::array();
  for (const Row& r : rows) {
    nlohmann::json j = {
        {"kernel", r.name}, {"set", r.set}, {"states", r.states}, {"per_second", r.per_second}};
    j["point_error"] = std::isnan(r.point_error) ? nlohmann::json() : nlohmann::json(r.point_error);
    j["point_error_max"] =
        std::isnan(r.point_error_max) ? nlohmann::json() : nlohmann::json(r.point_error_max);
    j["missed"] = r.missed;
    out.push_back(j);
  }
  std::ofstream(path) << out.dump(2) << "\n";
  std::printf("written: %s\n", path.c_str());
}

}  // namespace

int benchKernels(int argc, char** argv) {
  Args args(argc, argv, {"help", "cold", "warm"});
  if (args.flag("help")) {
    printHelp();
    return 0;
  }
  const Options o = parseOptions(args);
  if (mpi::rank() != 0) return 0;  // one core: rank 0 measures, other ranks have nothing to do

  std::printf("P-KERNELS: %d pairs per set, median of %d passes of ~%.2g s thread CPU time, %s\n",
              o.pairs, o.passes, o.seconds / o.passes,
              o.modes.size() == 2 ? "warm and cold pair states"
              : o.only_cold       ? "cold"
                                  : "warm");
  std::printf(
      "libccd 2.1: epa/mpr/dist tolerance %g (absolute; bodies of unit size), %lu "
      "iterations at most\n",
      kCcdTolerance, kCcdMaxIterations);
  const std::vector<PairSet> sets = makeSets(o.set_names, o.pairs);
  std::vector<std::unique_ptr<contact::Kernel>> kernels;
  std::vector<Measurement> all = prepareMeasurements(o, sets, kernels);
  measureAll(all, o.seconds, o.passes);
  std::vector<Row> rows;
  for (const Measurement& m : all) rows.push_back(m.row);
  printTable(rows, o.set_names);
  std::printf(
      "(ratios: throughput / %s on the same set; warm: pair states kept across passes, cold: "
      "none; 'miss': overlapping pairs reported apart)\n",
      kCcdGjkEpa);
  if (o.json_path) writeJson(rows, *o.json_path);
  return sink == 12345.678 ? 1 : 0;
}

}  // namespace polydem::app
