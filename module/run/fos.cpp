// Strength reduction and the search for F over groups of ranks (run/fos.h): every group settles
// the slope once and starts each of its trials from that state; the criterion is in
// fos_criterion.cpp, the settling and a trial in fos_trial.cpp.
#include "polydem/run/fos.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "polydem/core/error.h"
#include "polydem/core/logging.h"
#include "polydem/core/mpi_env.h"
#include "polydem/core/strings.h"
#include "polydem/dynamics/joint_law.h"
#include "polydem/particles/material.h"
#include "polydem/run/run_checkpoint.h"

namespace polydem::run {

namespace {

particles::MaterialTable materialTable(const setup::Setup& scene) {
  particles::MaterialTable table;
  for (const auto& m : scene.materials) table.add(m);
  for (const auto& i : scene.interactions) table.setInteraction(i.a, i.b, i.properties);
  table.finalize();
  return table;
}

const char* const kTrialOutcomes[] = {"stable", "failed", "undecided", "interrupted"};

int outcomeCode(const std::string& outcome) {
  for (int k = 0; k < 4; ++k) {
    if (outcome == kTrialOutcomes[k]) return k;
  }
  throw Error("fos: unknown trial outcome '" + outcome + "'");
}

// A trial as doubles, to be gathered from the group that ran it onto every rank.
void packTrial(const FosTrial& t, std::vector<double>& out) {
  double hash = 0.0;
  std::memcpy(&hash, &t.state_hash, sizeof hash);
  out.insert(out.end(), {t.factor, double(outcomeCode(t.outcome)), t.mean_displacement,
                         t.max_displacement, t.mean_speed, t.max_speed, t.force_ratio, t.time,
                         double(t.steps), double(t.extended), hash, t.wall_seconds, double(t.group),
                         double(t.round), t.max_move, double(t.history.size())});
  for (const FosSample& s : t.history) {
    out.insert(out.end(),
               {s.time, s.mean_displacement, s.mean_speed, s.max_speed, s.force_ratio, s.max_move});
  }
}

FosTrial unpackTrial(const double*& in) {
  FosTrial t;
  t.factor = in[0];
  t.outcome = kTrialOutcomes[static_cast<int>(in[1])];
  t.mean_displacement = in[2];
  t.max_displacement = in[3];
  t.mean_speed = in[4];
  t.max_speed = in[5];
  t.force_ratio = in[6];
  t.time = in[7];
  t.steps = static_cast<std::int64_t>(in[8]);
  t.extended = in[9] != 0.0;
  std::memcpy(&t.state_hash, &in[10], sizeof t.state_hash);
  t.wall_seconds = in[11];
  t.group = static_cast<int>(in[12]);
  t.round = static_cast<int>(in[13]);
  t.max_move = in[14];
  const auto n = static_cast<std::size_t>(in[15]);
  in += 16;
  for (std::size_t i = 0; i < n; ++i, in += 6) {
    t.history.push_back({in[0], in[1], in[2], in[3], in[4], in[5]});
  }
  return t;
}

// Every group root's trial, on every rank of `comm`, in group order.
std::vector<FosTrial> gatherTrials(const std::optional<FosTrial>& mine, MPI_Comm comm) {
  std::vector<double> buffer;
  if (mine) packTrial(*mine, buffer);
  const std::vector<double> all = mpi::allgatherv(buffer, comm);  // in rank order
  std::vector<FosTrial> trials;
  const double* p = all.data();
  while (p < all.data() + all.size()) trials.push_back(unpackTrial(p));
  std::sort(trials.begin(), trials.end(),
            [](const FosTrial& a, const FosTrial& b) { return a.group < b.group; });
  return trials;
}

// The bracket the decided trials give: the smallest failed F, and the largest stable F below it.
// Undecided trials bound nothing.
void bracket(const std::vector<FosTrial>& trials, FosResult& r) {
  r.stable.reset();
  r.failed.reset();
  for (const FosTrial& t : trials) {
    if (t.failed() && (!r.failed || t.factor < *r.failed)) r.failed = t.factor;
  }
  for (const FosTrial& t : trials) {
    if (t.stable() && (!r.failed || t.factor < *r.failed) && (!r.stable || t.factor > *r.stable)) {
      r.stable = t.factor;
    }
  }
}

const FosTrial* trialAt(const std::vector<FosTrial>& trials, double f) {
  for (const FosTrial& t : trials) {
    if (t.factor == f) return &t;
  }
  return nullptr;
}

// The factors of the next round; empty when done, with r.note saying why where the search did
// not resolve F.
std::vector<double> nextRound(FosResult& r, double f_min, double f_max, int groups) {
  const std::vector<FosTrial>& trials = r.trials;
  const FosTrial* lowest = trialAt(trials, f_min);
  if (!lowest) {
    if (groups == 1) return {f_min};
    std::vector<double> first;
    for (int k = 0; k < groups; ++k) first.push_back(f_min + (f_max - f_min) * k / (groups - 1));
    first.back() = f_max;
    return first;
  }
  if (!lowest->decided()) {
    r.note = cat("the trial at f_min = ", num(f_min), " is undecided: nothing is bracketed");
    return {};
  }
  if (lowest->failed()) {
    r.note = cat("the trial at f_min = ", num(f_min),
                 " failed (a decided trial): the factor of safety is below f_min");
    return {};
  }
  if (!r.failed) {
    const FosTrial* highest = trialAt(trials, f_max);
    if (!highest) return {f_max};
    r.note = highest->stable()
                 ? cat("the trial at f_max = ", num(f_max),
                       " is stable (a decided trial): the factor of safety is above f_max")
                 : cat("stable at F = ", num(*r.stable), ", the trial at f_max = ", num(f_max),
                       " is undecided and no trial failed: the factor of safety is above ",
                       num(*r.stable), ", not bracketed");
    return {};
  }
  const double lo = *r.stable, hi = *r.failed;
  for (const FosTrial& t : trials) {
    if (!t.decided() && t.factor > lo && t.factor < hi) {
      r.note =
          cat("the trial at F = ", num(t.factor), " is undecided (", t.outcome, " at ", num(t.time),
              " s): the factor of safety lies between the decided trials at ", num(lo),
              " (stable) and ", num(hi), " (failed), not resolved to ", num(r.resolution));
      return {};
    }
  }
  if (hi - lo <= r.resolution) {
    r.resolved = true;
    return {};
  }
  std::vector<double> next;
  for (int k = 1; k <= groups; ++k) next.push_back(lo + (hi - lo) * k / (groups + 1));
  // A resolution below round-off would split the bracket no further.
  if (next.front() <= lo || next.back() >= hi) {
    r.resolved = true;
    return {};
  }
  return next;
}

void logTrial(const FosTrial& t) {
  std::string how;
  if (t.stable()) {
    how = cat("came to rest at t = ", num(t.time), " s after moving ", num(t.mean_displacement),
              " m from the settled state (mean; largest ", num(t.max_displacement),
              " m; largest reach ", num(t.max_move), " of the block's size), force ratio ",
              num(t.force_ratio));
  } else {
    how = cat("at t = ", num(t.time), " s, mean displacement ", num(t.mean_displacement),
              " m (largest reach ", num(t.max_move), " of the block's size), mean speed ",
              num(t.mean_speed), " m/s, force ratio ", num(t.force_ratio));
  }
  log::info(cat("  F = ", num(t.factor), ": ", t.outcome, t.extended ? " (extended)" : "", " ", how,
                " (", num(t.wall_seconds), " s wall, group ", t.group, ")"));
}

// The trials of `prior` in complete rounds, and those of the round a signal cut short, by F.
void takePrior(const FosResult& prior, FosResult& r, std::vector<FosTrial>& cut_short) {
  for (const FosTrial& t : prior.trials) {
    (t.round < prior.rounds_complete ? r.trials : cut_short).push_back(t);
  }
  r.rounds_complete = prior.rounds_complete;
}

}  // namespace

setup::Setup reduceStrength(const setup::Setup& scene, double factor) {
  if (!(factor > 0.0) || !std::isfinite(factor)) {
    throw Error(cat("strength reduction: the factor must be > 0, got ", factor));
  }
  const particles::MaterialTable table = materialTable(scene);
  setup::Setup out = scene;
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
  // Every [[joint]] likewise, by its law's own rule (dynamics/joint_law.h).
  for (auto& j : out.joints) j.law = dynamics::reduceJointStrength(j.law, factor);

  // The joints [fos] leaves out keep the scene's strength.
  std::vector<char> reduced(scene.joints.size(), 0);
  for (const int k : reducedJoints(scene)) reduced[k] = 1;
  for (std::size_t k = 0; k < out.joints.size(); ++k) {
    if (!reduced[k]) out.joints[k] = scene.joints[k];
  }
  // Bolts are support, not the rock's strength: kept as given unless [fos] reduce_bolts asks that
  // their yield forces be divided by F too (their pretension stays an applied load, capped by the
  // reduced yield force).
  if (scene.fos.reduce_bolts) {
    for (auto& b : out.bolts) {
      b.axial_yield /= factor;
      b.shear_yield /= factor;
    }
  }
  return out;
}

std::optional<double> FosResult::factor() const {
  if (!stable || !failed || !resolved) return std::nullopt;
  return 0.5 * (*stable + *failed);
}

namespace {

// The settled state every trial of this group starts from: one settling per group, side by side,
// the same bits in each (only when a trial is still to run). Collective over `comm`.
FosStart settleGroup(const setup::Setup& scene, const FosCriterion& criterion, MPI_Comm group_comm,
                     MPI_Comm comm, FosResult& r) {
  const log::Level level = log::level();
  log::setLevel(std::min(level, log::Level::kWarning));
  FosStart start = settleForFos(scene, criterion, group_comm);
  log::setLevel(level);
  r.settle_steps = start.steps;
  r.settle_reached = start.reached && !start.moved;
  r.settle_used = !start.moved;
  r.settle_wall_seconds = mpi::allreduceMax(start.wall_seconds, comm);
  if (start.moved) {
    log::warning(
        cat("the unreduced slope does not stand even at the settling stage's friction "
            "(a block moved ",
            num(criterion.moved_fraction),
            " of its size while it settled): every trial starts from the scene as "
            "placed"));
  } else if (!start.interrupted) {
    log::info(
        cat("settled the unreduced slope in ", r.settle_steps, " steps (",
            r.settle_reached ? "at rest by the criterion" : "NOT at rest at the stage's step limit",
            ", ", num(r.settle_wall_seconds), " s wall): every trial starts there"));
  }
  return start;
}

// This group's trial of the round (none when the round has fewer factors than groups), kept on
// the group's first rank only: one copy per trial. A trial that finished before a signal stopped
// the last run is taken as it was (the same bits again).
std::optional<FosTrial> groupTrial(const setup::Setup& scene, const FosStart& start,
                                   const std::vector<double>& round, int group,
                                   const std::vector<FosTrial>& cut_short,
                                   const FosCriterion& criterion, MPI_Comm group_comm,
                                   int rounds_complete) {
  std::optional<FosTrial> mine;
  if (group >= static_cast<int>(round.size())) return mine;
  if (const FosTrial* done = trialAt(cut_short, round[group])) {
    mine = *done;
  } else {
    const log::Level level = log::level();
    log::setLevel(std::min(level, log::Level::kWarning));  // no run chatter from the trials
    mine = runFosTrial(scene, start, round[group], criterion, group_comm);
    log::setLevel(level);
  }
  mine->group = group;
  mine->round = rounds_complete;
  if (mpi::rank(group_comm) != 0) mine.reset();
  return mine;
}

// A stable trial above a failed one: the outcome is not monotonic in F, which the note says.
void noteNonMonotonic(FosResult& r) {
  for (const FosTrial& t : r.trials) {
    if (t.stable() && r.failed && t.factor > *r.failed) {
      r.note += cat(r.note.empty() ? "" : "; ", "stable at F = ", num(t.factor),
                    " above a failed trial: the outcome is not monotonic in F");
    }
  }
}

}  // namespace

FosResult findFactorOfSafety(const setup::Setup& scene, const FosCriterion& criterion, int groups,
                             MPI_Comm comm, const FosResult* prior) {
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
  std::vector<FosTrial> cut_short;  // finished trials of a round a signal stopped
  if (prior) {
    takePrior(*prior, r, cut_short);
    for (const FosTrial& t : r.trials) logTrial(t);
  }
  bracket(r.trials, r);
  std::optional<FosStart> start;
  const double f_min = scene.fos.f_min, f_max = scene.fos.f_max;
  for (std::vector<double> round = nextRound(r, f_min, f_max, groups); !round.empty();
       round = nextRound(r, f_min, f_max, groups)) {
    if (const int sig = stopSignalOnAnyRank(comm)) {  // between rounds
      r.complete = false;
      r.stop_signal = signalName(sig);
      break;
    }
    // Collective over `comm`: every group settles in the first round.
    if (!start) start = settleGroup(scene, criterion, group_comm, comm, r);
    const std::optional<FosTrial> mine = groupTrial(scene, *start, round, group, cut_short,
                                                    criterion, group_comm, r.rounds_complete);
    bool interrupted = false;
    std::vector<FosTrial> finished;
    for (const FosTrial& t : gatherTrials(mine, comm)) {
      if (t.outcome == "interrupted") {
        interrupted = true;
        continue;
      }
      finished.push_back(t);
    }
    const int sig = stopSignalOnAnyRank(comm);
    if (interrupted || sig != 0) {
      // A signal during the round: keep what finished, as the cut-short round's trials.
      for (const FosTrial& t : finished) {
        if (!trialAt(cut_short, t.factor)) cut_short.push_back(t);
      }
      r.complete = false;
      r.stop_signal = signalName(sig);
      break;
    }
    for (const FosTrial& t : finished) {
      logTrial(t);
      r.trials.push_back(t);
    }
    ++r.rounds_complete;
    cut_short.clear();
    bracket(r.trials, r);
  }
  MPI_Comm_free(&group_comm);
  if (!r.complete) {
    r.note =
        cat("stopped by ", r.stop_signal, " after ", r.trials.size(), " trials in complete rounds");
    for (const FosTrial& t : cut_short) r.trials.push_back(t);  // kept for the continuation
    return r;
  }
  noteNonMonotonic(r);
  return r;
}

}  // namespace polydem::run
