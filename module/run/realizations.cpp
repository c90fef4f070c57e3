// The realizations of a study over groups of ranks (run/realizations.h).
#include "polydem/run/realizations.h"

#include <algorithm>
#include <chrono>
#include <cstring>

#include "polydem/core/error.h"
#include "polydem/core/logging.h"
#include "polydem/core/mpi_env.h"
#include "polydem/core/strings.h"
#include "polydem/output/output_file.h"
#include "polydem/run/fos.h"
#include "polydem/run/run_checkpoint.h"

namespace polydem::run {

namespace {

const char* const kRealizationOutcomes[] = {"resolved", "below f_min", "above f_max",
                                            "not resolved", "invalid"};

double bitsOf(std::uint64_t h) {
  double d = 0.0;
  std::memcpy(&d, &h, sizeof d);
  return d;
}

std::uint64_t hashOf(double d) {
  std::uint64_t h = 0;
  std::memcpy(&h, &d, sizeof h);
  return h;
}

constexpr double kNone = -1.0;  // an absent bound (F > 0 always)

void packResult(const RealizationResult& r, std::vector<double>& out) {
  int code = 0;
  while (r.outcome != kRealizationOutcomes[code]) ++code;
  out.insert(out.end(),
             {double(r.index), bitsOf(r.seed), double(code), r.stable.value_or(kNone),
              r.failed.value_or(kNone), r.f_min, r.f_max, double(r.trials), r.wall_seconds,
              double(r.group), double(r.values.size()), double(r.trial_hashes.size())});
  out.insert(out.end(), r.values.begin(), r.values.end());
  for (const std::uint64_t h : r.trial_hashes) out.push_back(bitsOf(h));
}

RealizationResult unpackResult(const double*& in) {
  RealizationResult r;
  r.index = static_cast<std::int64_t>(in[0]);
  r.seed = hashOf(in[1]);
  r.outcome = kRealizationOutcomes[static_cast<int>(in[2])];
  if (in[3] != kNone) r.stable = in[3];
  if (in[4] != kNone) r.failed = in[4];
  if (r.outcome == std::string("resolved")) r.factor = 0.5 * (*r.stable + *r.failed);
  r.f_min = in[5];
  r.f_max = in[6];
  r.trials = static_cast<int>(in[7]);
  r.wall_seconds = in[8];
  r.group = static_cast<int>(in[9]);
  const auto values = static_cast<std::size_t>(in[10]), hashes = static_cast<std::size_t>(in[11]);
  in += 12;
  r.values.assign(in, in + values);
  in += values;
  for (std::size_t k = 0; k < hashes; ++k) r.trial_hashes.push_back(hashOf(*in++));
  return r;
}

// Every group root's result (and every group's error), on every rank, in realization order.
std::vector<RealizationResult> gather(const std::optional<RealizationResult>& mine, MPI_Comm comm) {
  std::vector<double> buffer;
  if (mine) packResult(*mine, buffer);
  const std::vector<double> all = mpi::allgatherv(buffer, comm);  // in rank order
  std::vector<RealizationResult> out;
  for (const double* p = all.data(); p < all.data() + all.size();) out.push_back(unpackResult(p));
  std::sort(out.begin(), out.end(), [](const auto& a, const auto& b) { return a.index < b.index; });
  return out;
}

// The search's outcome for one realization.
RealizationResult summarize(const scene::Realization& real, const setup::Setup& scene,
                            const FosResult& search) {
  RealizationResult r;
  r.index = real.index;
  r.seed = real.seed;
  r.values = real.values;
  r.f_min = scene.fos.f_min;
  r.f_max = scene.fos.f_max;
  r.stable = search.stable;
  r.failed = search.failed;
  r.trials = static_cast<int>(search.trials.size());
  for (const FosTrial& t : search.trials) r.trial_hashes.push_back(t.state_hash);
  const auto at = [&](double f) {
    return std::find_if(search.trials.begin(), search.trials.end(),
                        [f](const FosTrial& t) { return t.factor == f; });
  };
  if (search.factor()) {
    r.outcome = "resolved";
    r.factor = search.factor();
  } else if (const auto lo = at(r.f_min); lo != search.trials.end() && lo->failed()) {
    r.outcome = "below f_min";
  } else if (const auto hi = at(r.f_max); hi != search.trials.end() && hi->stable()) {
    r.outcome = "above f_max";
  } else {
    r.outcome = "not resolved";
  }
  return r;
}

RealizationResult invalid(const scene::Realization& real) {
  RealizationResult r;
  r.index = real.index;
  r.seed = real.seed;
  r.values = real.values;
  r.outcome = "invalid";
  return r;
}

}  // namespace

std::optional<bool> RealizationResult::fails() const {
  if (factor) return *factor < 1.0;
  // Without a resolved F, the decided trials still bound it: stable <= F < failed.
  if (failed && *failed <= 1.0) return true;
  if (stable && *stable >= 1.0) return false;
  return std::nullopt;
}

bool runRealizations(const scene::Study& study, const std::vector<std::int64_t>& todo, int groups,
                     MPI_Comm comm,
                     const std::function<void(const std::vector<RealizationResult>&)>& round_done) {
  const int ranks = mpi::size(comm), rank = mpi::rank(comm);
  if (groups < 1 || ranks % groups != 0) {
    throw Error(cat("realizations: ", groups, " groups do not divide ", ranks, " ranks"));
  }
  const int per_group = ranks / groups, group = rank / per_group;
  MPI_Comm group_comm;
  MPI_Comm_split(comm, group, rank, &group_comm);
  bool complete = true;
  const log::Level level = log::level();
  for (std::size_t first = 0; first < todo.size(); first += static_cast<std::size_t>(groups)) {
    if (stopSignalOnAnyRank(comm) != 0) {
      complete = false;
      break;
    }
    std::optional<RealizationResult> mine;
    std::string error;
    bool stopped = false;
    if (first + static_cast<std::size_t>(group) < todo.size()) {
      const auto start = std::chrono::steady_clock::now();
      log::setLevel(std::min(level, log::Level::kWarning));  // no trial chatter
      const scene::Realization real = scene::drawRealization(study, todo[first + group]);
      std::optional<setup::Setup> scene;
      try {
        scene = scene::realizationScene(study, real);
      } catch (const InputError& e) {
        // A draw that gives no scene (a rock mass that cannot be cut so): recorded, not run.
        if (mpi::rank(group_comm) == 0) log::rankWarning(e.what());
        mine = invalid(real);
      }
      try {
        if (scene) {
          const FosResult search = findFactorOfSafety(*scene, fosCriterion(*scene), 1, group_comm);
          stopped = !search.complete;
          mine = summarize(real, *scene, search);
        }
        mine->group = group;
        mine->wall_seconds =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      } catch (const Error& e) {
        error = e.what();
      }
      log::setLevel(level);
      if (stopped || mpi::rank(group_comm) != 0) mine.reset();  // one copy of each
    }
    output::throwIfAnyRankFailed(error, comm);
    std::vector<RealizationResult> round = gather(mine, comm);
    if (stopSignalOnAnyRank(comm) != 0) {
      // Keep the realizations this round finished before the signal; the others run again.
      if (!round.empty()) round_done(round);
      complete = false;
      break;
    }
    round_done(round);
  }
  MPI_Comm_free(&group_comm);
  return complete;
}

}  // namespace polydem::run
