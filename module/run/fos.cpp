#include "polydem/run/fos.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>

#include "polydem/core/error.h"
#include "polydem/core/logging.h"
#include "polydem/core/mpi_env.h"
#include "polydem/core/strings.h"
#include "polydem/geometry/convex_polyhedron.h"
#include "polydem/particles/material.h"
#include "polydem/run/free_motion.h"
#include "polydem/sim/simulation.h"

namespace polydem::sim {

namespace {

particles::MaterialTable materialTable(const io::Scene& scene) {
  particles::MaterialTable table;
  for (const auto& m : scene.materials) table.add(m);
  for (const auto& i : scene.interactions) table.setInteraction(i.a, i.b, i.properties);
  table.finalize();
  return table;
}

// The mean size (cube root of the mean volume) of the watched free blocks.
double meanBlockSize(const io::Scene& scene, const std::string& prefix) {
  double volume = 0.0;
  int count = 0;
  for (const auto& p : scene.particles) {
    if (p.fixed || p.driver >= 0 || !matchesPrefix(p.label, prefix)) continue;
    volume += geometry::ConvexPolyhedron::fromPoints(scene.shapes[p.shape].vertices).volume();
    ++count;
  }
  if (count == 0) {
    throw InputError(scene.file, scene.fos.line,
                     prefix.empty()
                         ? std::string("[fos]: the scene has no free particle")
                         : "[fos] label_prefix: no free particle is labelled '" + prefix + "_...'");
  }
  return std::cbrt(volume / count);
}

enum Outcome { kStable = 0, kFailed = 1, kMoving = 2 };
const char* outcomeName(int code) {
  return code == kStable ? "stable" : code == kFailed ? "failed" : "moving";
}

// A trial as doubles, to be gathered from the group that ran it onto every rank.
void pack(const FosTrial& t, std::vector<double>& out) {
  const int code = t.outcome == "stable" ? kStable : t.outcome == "failed" ? kFailed : kMoving;
  double hash = 0.0;
  std::memcpy(&hash, &t.state_hash, sizeof hash);
  out.insert(out.end(),
             {t.factor, double(code), t.mean_displacement, t.max_displacement, t.mean_speed, t.time,
              double(t.steps), hash, t.wall_seconds, double(t.group), double(t.history.size())});
  for (const FosSample& s : t.history) {
    out.insert(out.end(), {s.time, s.mean_displacement, s.mean_speed});
  }
}

FosTrial unpack(const double*& in) {
  FosTrial t;
  t.factor = in[0];
  t.outcome = outcomeName(static_cast<int>(in[1]));
  t.mean_displacement = in[2];
  t.max_displacement = in[3];
  t.mean_speed = in[4];
  t.time = in[5];
  t.steps = static_cast<std::int64_t>(in[6]);
  std::memcpy(&t.state_hash, &in[7], sizeof t.state_hash);
  t.wall_seconds = in[8];
  t.group = static_cast<int>(in[9]);
  const auto n = static_cast<std::size_t>(in[10]);
  in += 11;
  for (std::size_t i = 0; i < n; ++i, in += 3) t.history.push_back({in[0], in[1], in[2]});
  return t;
}

// Every group root's trial, on every rank of `comm`, in group order.
std::vector<FosTrial> gatherTrials(const std::optional<FosTrial>& mine, MPI_Comm comm) {
  std::vector<double> buffer;
  if (mine) pack(*mine, buffer);
  const int ranks = mpi::size(comm);
  int count = static_cast<int>(buffer.size());
  std::vector<int> counts(ranks), offsets(ranks, 0);
  MPI_Allgather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, comm);
  for (int r = 1; r < ranks; ++r) offsets[r] = offsets[r - 1] + counts[r - 1];
  std::vector<double> all(static_cast<std::size_t>(offsets.back() + counts.back()));
  MPI_Allgatherv(buffer.data(), count, MPI_DOUBLE, all.data(), counts.data(), offsets.data(),
                 MPI_DOUBLE, comm);
  std::vector<FosTrial> trials;
  const double* p = all.data();
  while (p < all.data() + all.size()) trials.push_back(unpack(p));
  std::sort(trials.begin(), trials.end(),
            [](const FosTrial& a, const FosTrial& b) { return a.group < b.group; });
  return trials;
}

// The bracket the trials give: the smallest failed F, and the largest stable F below it.
void bracket(const std::vector<FosTrial>& trials, FosResult& r) {
  r.stable.reset();
  r.failed.reset();
  for (const FosTrial& t : trials) {
    if (!t.stable() && (!r.failed || t.factor < *r.failed)) r.failed = t.factor;
  }
  for (const FosTrial& t : trials) {
    if (t.stable() && (!r.failed || t.factor < *r.failed) && (!r.stable || t.factor > *r.stable)) {
      r.stable = t.factor;
    }
  }
}

// The factors of the next round (empty when done).
std::vector<double> nextRound(const std::vector<FosTrial>& trials, const FosResult& r, double f_min,
                              double f_max, int groups) {
  const auto tried = [&trials](double f) {
    return std::any_of(trials.begin(), trials.end(),
                       [f](const FosTrial& t) { return t.factor == f; });
  };
  std::vector<double> next;
  if (!tried(f_min)) {
    if (groups == 1) return {f_min};
    for (int k = 0; k < groups; ++k) next.push_back(f_min + (f_max - f_min) * k / (groups - 1));
    next.back() = f_max;
    return next;
  }
  if (r.failed && *r.failed == f_min) return {};  // below the range
  if (!r.failed && !tried(f_max)) return {f_max};
  if (!r.failed) return {};  // stable at f_max: above the range
  const double lo = *r.stable, hi = *r.failed;
  if (hi - lo <= r.resolution) return {};
  for (int k = 1; k <= groups; ++k) next.push_back(lo + (hi - lo) * k / (groups + 1));
  // A resolution below round-off would split the bracket no further.
  if (next.front() <= lo || next.back() >= hi) return {};
  return next;
}

}  // namespace

std::vector<std::pair<int, int>> reducedPairs(const io::Scene& scene) {
  if (!scene.fos.interactions.empty()) return scene.fos.interactions;
  std::vector<std::pair<int, int>> pairs;
  const int n = static_cast<int>(scene.materials.size());
  for (int a = 0; a < n; ++a) {
    for (int b = a; b < n; ++b) pairs.emplace_back(a, b);
  }
  return pairs;
}

io::Scene reduceStrength(const io::Scene& scene, double factor) {
  if (!(factor > 0.0) || !std::isfinite(factor)) {
    throw Error(cat("strength reduction: the factor must be > 0, got ", factor));
  }
  const particles::MaterialTable table = materialTable(scene);
  io::Scene out = scene;
  for (const auto& [a, b] : reducedPairs(scene)) {
    particles::ContactProperties p = table.pair(a, b);
    p.friction_angle = radToDeg(std::atan(std::tan(degToRad(p.friction_angle)) / factor));
    p.cohesion /= factor;
    auto it = std::find_if(out.interactions.begin(), out.interactions.end(), [&](const auto& i) {
      return std::min(i.a, i.b) == a && std::max(i.a, i.b) == b;
    });
    if (it == out.interactions.end()) {
      out.interactions.push_back({a, b, p});
    } else {
      it->properties = p;
    }
  }
  // Every [[joint]] likewise: its friction, cohesion and tensile strength.
  for (auto& j : out.joints) {
    j.friction_angle = radToDeg(std::atan(std::tan(degToRad(j.friction_angle)) / factor));
    j.cohesion /= factor;
    j.tensile_strength /= factor;
  }
  return out;
}

FosCriterion fosCriterion(const io::Scene& scene) {
  const io::FosSpec& f = scene.fos;
  FosCriterion c;
  if (!f.max_time) {
    throw InputError(scene.file, f.line,
                     "[fos]: give max_time (how long a trial may run before it counts as still "
                     "moving), in the scene or as --max-time");
  }
  c.max_time = *f.max_time;
  c.settle_time = f.settle_time.value_or(0.25 * c.max_time);
  if (!(c.settle_time < c.max_time)) {
    throw InputError(scene.file, f.line, "[fos]: settle_time must be shorter than max_time");
  }
  c.speed_limit = f.speed_limit;
  c.label_prefix = f.label_prefix;
  c.displacement_limit = f.displacement_limit.value_or(0.1 * meanBlockSize(scene, f.label_prefix));
  c.check_every = f.check_every;
  return c;
}

FosTrial runFosTrial(const io::Scene& scene, double factor, const FosCriterion& criterion,
                     MPI_Comm comm) {
  const auto wall0 = std::chrono::steady_clock::now();
  io::Scene reduced = reduceStrength(scene, factor);
  reduced.end_time.reset();
  reduced.steps.reset();
  Simulation sim(reduced, comm);
  const FreeMotionMeter meter(sim, criterion.label_prefix);
  sim.runEquilibrium();
  FosTrial t;
  t.factor = factor;
  const double t0 = sim.time();
  while (true) {
    for (std::int64_t i = 0; i < criterion.check_every; ++i) sim.step();
    const FreeMotion m = meter.measure(sim);
    const double time = sim.time() - t0;
    t.history.push_back({time, m.mean_displacement, m.mean_speed});
    t.mean_displacement = m.mean_displacement;
    t.max_displacement = m.max_displacement;
    t.mean_speed = m.mean_speed;
    t.time = time;
    // The same values on every rank, so every rank decides alike.
    if (m.mean_displacement > criterion.displacement_limit) {
      t.outcome = "failed";
    } else if (time >= criterion.settle_time && m.mean_speed < criterion.speed_limit) {
      t.outcome = "stable";
    } else if (time >= criterion.max_time) {
      t.outcome = "moving";
    }
    if (!t.outcome.empty()) break;
  }
  t.steps = sim.stepCount();
  t.state_hash = sim.stateHash().combined;
  t.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  return t;
}

std::optional<double> FosResult::factor() const {
  if (!stable || !failed) return std::nullopt;
  return 0.5 * (*stable + *failed);
}

FosResult findFactorOfSafety(const io::Scene& scene, const FosCriterion& criterion, int groups,
                             MPI_Comm comm) {
  const int ranks = mpi::size(comm), rank = mpi::rank(comm);
  if (groups < 1 || ranks % groups != 0) {
    throw Error(cat("fos: ", groups, " groups do not divide ", ranks, " ranks"));
  }
  const int per_group = ranks / groups, group = rank / per_group;
  MPI_Comm group_comm;
  MPI_Comm_split(comm, group, rank, &group_comm);
  FosResult r;
  r.resolution = scene.fos.resolution;
  r.groups = groups;
  r.ranks = ranks;
  const log::Level level = log::level();
  for (std::vector<double> round = nextRound(r.trials, r, scene.fos.f_min, scene.fos.f_max, groups);
       !round.empty(); round = nextRound(r.trials, r, scene.fos.f_min, scene.fos.f_max, groups)) {
    std::optional<FosTrial> mine;
    if (group < static_cast<int>(round.size())) {
      log::setLevel(std::min(level, log::Level::kWarning));  // no run chatter from the trials
      mine = runFosTrial(scene, round[group], criterion, group_comm);
      log::setLevel(level);
      mine->group = group;
      if (mpi::rank(group_comm) != 0) mine.reset();  // one copy per trial
    }
    for (const FosTrial& t : gatherTrials(mine, comm)) {
      log::info(cat("  F = ", num(t.factor), ": ", t.outcome, " at t = ", num(t.time),
                    " s, mean displacement ", num(t.mean_displacement), " m, mean speed ",
                    num(t.mean_speed), " m/s (", num(t.wall_seconds), " s wall, group ", t.group,
                    ")"));
      r.trials.push_back(t);
    }
    bracket(r.trials, r);
  }
  MPI_Comm_free(&group_comm);
  if (r.failed && *r.failed == scene.fos.f_min) {
    r.note = cat("fails at f_min = ", num(scene.fos.f_min), ": the factor of safety is below it");
  } else if (!r.failed) {
    r.note = cat("stable at f_max = ", num(scene.fos.f_max), ": the factor of safety is above it");
  }
  for (const FosTrial& t : r.trials) {
    if (t.stable() && r.failed && t.factor > *r.failed) {
      r.note += cat(r.note.empty() ? "" : "; ", "stable at F = ", num(t.factor),
                    " above a failed trial: the outcome is not monotonic in F");
    }
  }
  return r;
}

}  // namespace polydem::sim
