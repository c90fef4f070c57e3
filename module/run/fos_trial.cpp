// One trial of `polydem fos` (run/fos.h): the scene at reduced strength run as a static solution
// and judged every check_every steps, until stable, failed, undecided at the cap, or stopped.
#include <algorithm>
#include <chrono>

#include "polydem/core/mpi_env.h"
#include "polydem/core/test_pause.h"
#include "polydem/run/fos.h"
#include "polydem/run/free_motion.h"
#include "polydem/run/run_checkpoint.h"
#include "polydem/sim/simulation.h"

namespace polydem::sim {

namespace {

// Whether some rank of `comm` has received a stop signal (collective).
bool stopRequested(MPI_Comm comm) {
  int local = stopSignalReceived(), global = 0;
  MPI_Allreduce(&local, &global, 1, MPI_INT, MPI_MAX, comm);
  return global != 0;
}

// The mean of the samples' mean speeds with time in (from, to].
double meanSpeedBetween(const std::vector<FosSample>& h, double from, double to) {
  double sum = 0.0;
  int n = 0;
  for (const FosSample& s : h) {
    if (s.time > from && s.time <= to) {
      sum += s.mean_speed;
      ++n;
    }
  }
  return n > 0 ? sum / n : 0.0;
}

// The last sample at or before `time` (the first one if none is).
const FosSample& sampleAt(const std::vector<FosSample>& h, double time) {
  std::size_t k = 0;
  while (k + 1 < h.size() && h[k + 1].time <= time) ++k;
  return h[k];
}

struct Peaks {
  double max_speed = 0.0, mean_speed = 0.0;
};

// "stable", "failed" or "" (not yet) at the latest sample of `h`.
std::string judge(const std::vector<FosSample>& h, const Peaks& peak, const FosCriterion& c) {
  const FosSample& now = h.back();
  if (c.displacement_limit && now.mean_displacement > *c.displacement_limit) return "failed";
  if (now.time < c.window) return "";
  // At rest: the forces balance and every watched block's speed has died away.
  if (now.force_ratio < c.force_ratio && now.max_speed <= c.speed_decay * peak.max_speed &&
      (!c.speed_limit || now.mean_speed < *c.speed_limit)) {
    return "stable";
  }
  // Still going: the speeds of the window's second half are no lower than those of its first
  // half (averages, so that a decaying oscillation is not read as growth), the displacement grew
  // in both halves, and the speed is more than the noise left after a decay.
  const double start = now.time - c.window, middle = now.time - 0.5 * c.window;
  const FosSample& s0 = sampleAt(h, start);
  const FosSample& s1 = sampleAt(h, middle);
  const bool speeds_kept =
      meanSpeedBetween(h, middle, now.time) >= meanSpeedBetween(h, start, middle);
  const bool growing =
      s1.mean_displacement > s0.mean_displacement && now.mean_displacement > s1.mean_displacement;
  if (speeds_kept && growing && now.mean_speed > c.speed_decay * peak.mean_speed) return "failed";
  return "";
}

}  // namespace

FosTrial runFosTrial(const io::Scene& scene, double factor, const FosCriterion& criterion,
                     MPI_Comm comm, FosTrialObserver* observer) {
  const auto wall0 = std::chrono::steady_clock::now();
  io::Scene reduced = reduceStrength(scene, factor);
  for (auto& m : reduced.materials) m.local_damping = criterion.local_damping;  // static solution
  reduced.end_time.reset();
  reduced.steps.reset();
  Simulation sim(reduced, comm);
  const FreeMotionMeter meter(sim, criterion.label_prefix);
  FosTrial t;
  t.factor = factor;
  sim.setStepHook([comm] { return stopRequested(comm); });
  sim.runEquilibrium();
  sim.setStepHook(nullptr);
  bool interrupted = stopRequested(comm);
  const double t0 = sim.time();
  Peaks peak;
  const auto sample = [&] {
    const FreeMotion m = meter.measure(sim);
    const double ratio = sim.monitors().force_ratio;  // the same on every rank
    const double time = sim.time() - t0;
    t.history.push_back({time, m.mean_displacement, m.mean_speed, m.max_speed, ratio});
    peak.max_speed = std::max(peak.max_speed, m.max_speed);
    peak.mean_speed = std::max(peak.mean_speed, m.mean_speed);
    t.mean_displacement = m.mean_displacement;
    t.max_displacement = m.max_displacement;
    t.mean_speed = m.mean_speed;
    t.max_speed = m.max_speed;
    t.force_ratio = ratio;
    t.time = time;
  };
  if (!interrupted) sample();
  if (observer && !interrupted) observer->started(sim);
  testPause("fos-trial");  // test hook: a signal here stops the trial after its next step
  while (!interrupted && t.outcome.empty()) {
    for (std::int64_t i = 0; i < criterion.check_every && !interrupted; ++i) {
      sim.step();
      interrupted = stopRequested(comm);  // finish this step, then stop
    }
    if (interrupted) break;
    sample();
    if (observer) observer->checked(sim);
    t.outcome = judge(t.history, peak, criterion);
    if (t.outcome.empty() && t.time >= criterion.time_cap) t.outcome = "undecided";
  }
  if (interrupted) t.outcome = "interrupted";
  t.extended = t.time > criterion.max_time;
  t.steps = sim.stepCount();
  t.state_hash = sim.stateHash().combined;
  if (observer && !interrupted) observer->decided(sim, t);
  t.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  return t;
}

}  // namespace polydem::sim
