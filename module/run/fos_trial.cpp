// One trial of `polydem fos` (run/fos.h): the scene at reduced strength, started from the settled
// state of the unreduced slope, run as a static solution and judged every check_every steps,
// until stable, failed, undecided at the cap, or stopped.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>

#include "polydem/core/exact_sum.h"
#include "polydem/core/mpi_env.h"
#include "polydem/core/test_pause.h"
#include "polydem/run/fos.h"
#include "polydem/run/free_motion.h"
#include "polydem/run/run_checkpoint.h"
#include "polydem/sim/simulation.h"

namespace polydem::run {

namespace {

// Whether some rank of `comm` has received a stop signal (collective).
bool stopRequested(MPI_Comm comm) {
  int local = stopSignalReceived(), global = 0;
  MPI_Allreduce(&local, &global, 1, MPI_INT, MPI_MAX, comm);
  return global != 0;
}

double secondsSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// The watched blocks' motion from the state the trial starts in (the settled slope), on every
// rank: the start poses by uid are summed over the ranks once (each block has one owner).
class TrialMeter {
 public:
  TrialMeter(const sim::Simulation& sim, const std::string& label_prefix) {
    Uid top = 0;
    for (const auto& p : sim.scene().particles) top = std::max(top, p.uid);
    const std::size_t n = top + 1;
    chosen_.assign(n, 0);
    for (const auto& p : sim.scene().particles) {
      if (!p.fixed && p.driver < 0 && matchesPrefix(p.label, label_prefix)) chosen_[p.uid] = 1;
    }
    std::vector<double> pose(7 * n, 0.0);  // position, orientation (w, x, y, z)
    const auto& storage = sim.particles();
    for (std::size_t i = 0; i < storage.localCount(); ++i) {
      const auto& p = storage[i];
      if (!p.isFree() || !isChosen(p.uid)) continue;
      double* q = &pose[7 * p.uid];
      q[0] = p.position.x();
      q[1] = p.position.y();
      q[2] = p.position.z();
      q[3] = p.orientation.w();
      q[4] = p.orientation.x();
      q[5] = p.orientation.y();
      q[6] = p.orientation.z();
    }
    // Exact: every entry is one rank's value plus zeros.
    MPI_Allreduce(MPI_IN_PLACE, pose.data(), static_cast<int>(pose.size()), MPI_DOUBLE, MPI_SUM,
                  sim.comm());
    position_.resize(n);
    orientation_.resize(n);
    for (std::size_t u = 0; u < n; ++u) {
      const double* q = &pose[7 * u];
      position_[u] = Vec3(q[0], q[1], q[2]);
      orientation_[u] = Quat(q[3], q[4], q[5], q[6]);
    }
  }

  // Collective: the sample at `time` (s since the trial's start) with the force ratio given.
  FosSample measure(const sim::Simulation& sim, double time, double force_ratio,
                    double& max_displacement) const {
    ExactSum displacement, speed;
    double local_max[3] = {0.0, 0.0, 0.0};  // displacement, speed, reach / size
    std::int64_t count = 0;
    const auto& storage = sim.particles();
    for (std::size_t i = 0; i < storage.localCount(); ++i) {
      const auto& p = storage[i];
      if (!p.isFree() || !isChosen(p.uid)) continue;
      ++count;
      const double d = (p.position - position_[p.uid]).norm();
      const double turn =
          Eigen::AngleAxisd(p.orientation * orientation_[p.uid].conjugate()).angle();
      const auto& shape = sim.shapes()[p.shape];
      const double reach = d + std::abs(turn) * shape.circumradius;
      displacement += d;
      speed += p.velocity.norm();
      local_max[0] = std::max(local_max[0], d);
      local_max[1] = std::max(local_max[1], p.velocity.norm());
      local_max[2] = std::max(local_max[2], reach / std::cbrt(shape.volume));
    }
    displacement.allreduce(sim.comm());
    speed.allreduce(sim.comm());
    double global_max[3];
    MPI_Allreduce(local_max, global_max, 3, MPI_DOUBLE, MPI_MAX, sim.comm());
    const double n =
        std::max<double>(1.0, static_cast<double>(mpi::allreduceSum(count, sim.comm())));
    max_displacement = global_max[0];
    return {time,         displacement.value() / n, speed.value() / n, global_max[1], force_ratio,
            global_max[2]};
  }

 private:
  bool isChosen(Uid uid) const { return uid < chosen_.size() && chosen_[uid]; }
  std::vector<char> chosen_;  // by uid
  std::vector<Vec3> position_;
  std::vector<Quat> orientation_;
};

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

// "stable", "failed" or "" (not yet) at the latest sample of `h` (run/fos.h, the criterion).
std::string judge(const std::vector<FosSample>& h, const Peaks& peak, const FosCriterion& c) {
  const FosSample& now = h.back();
  // Moved from where it stood, by a share of a block's size no elastic settling reaches.
  if (now.max_move > c.moved_fraction) return "failed";
  if (c.displacement_limit && now.mean_displacement > *c.displacement_limit) return "failed";
  if (now.time < c.window) return "";
  const double start = now.time - c.window, middle = now.time - 0.5 * c.window;
  const FosSample& s0 = sampleAt(h, start);
  const FosSample& s1 = sampleAt(h, middle);
  // At rest: the forces balance and every watched block's speed has died away; or the blocks
  // have stopped moving: over the window the largest relative reach grew by less than
  // rest_fraction, and no faster in its second half than in its first (a motion from rest under
  // a net force grows faster and faster; what is left is round-off and elastic jitter, which
  // can keep R above force_ratio, as in S-CUT-SLOPE-53 at the thesis's time step).
  const bool balanced =
      now.force_ratio < c.force_ratio && now.max_speed <= c.speed_decay * peak.max_speed;
  const bool still = now.max_move - s0.max_move < c.rest_fraction &&
                     now.max_move - s1.max_move <= s1.max_move - s0.max_move;
  if ((balanced || still) && (!c.speed_limit || now.mean_speed < *c.speed_limit)) return "stable";
  // Still going: the speeds of the window's second half are no lower than those of its first
  // half (averages, so that a decaying oscillation is not read as growth), the largest relative
  // reach grew in both halves and by more than growth_fraction over the window (a creep of a
  // millionth of a block is not a mechanism), and the speed is more than the noise left after a
  // decay.
  const bool speeds_kept =
      meanSpeedBetween(h, middle, now.time) >= meanSpeedBetween(h, start, middle);
  const bool growing = s1.max_move > s0.max_move && now.max_move > s1.max_move &&
                       now.max_move - s0.max_move > c.growth_fraction;
  if (speeds_kept && growing && now.mean_speed > c.speed_decay * peak.mean_speed) return "failed";
  return "";
}

}  // namespace

FosStart settleForFos(const setup::Setup& scene, const FosCriterion& criterion, MPI_Comm comm) {
  const auto wall0 = std::chrono::steady_clock::now();
  setup::Setup settle = scene;
  if (!settle.equilibrium.enabled) {
    settle.equilibrium = setup::EquilibriumSpec{};
    settle.equilibrium.enabled = true;
    settle.equilibrium.force_ratio = criterion.force_ratio;
    settle.equilibrium.max_steps =
        std::max<std::int64_t>(kFosMinTrialSteps, std::llround(criterion.time_cap / scene.dt));
  }
  sim::Simulation sim(settle, comm);
  // Judged as a trial is, from where the scene put the blocks: settled when the force ratio
  // falls below the stage's (the stage ends itself) or the blocks have stopped moving; a slope
  // that leaves its place meanwhile (a column that topples whatever its friction) stands at no
  // strength, and its trials start from the scene as placed.
  const TrialMeter meter(sim, criterion.label_prefix);
  FosStart start;
  std::vector<FosSample> history;
  Peaks peak;
  std::int64_t steps = 0;
  bool still = false;
  sim.setStepHook([&] {
    if (stopRequested(comm)) return true;
    if (++steps % criterion.check_every != 0) return false;
    double largest = 0.0;
    history.push_back(meter.measure(sim, static_cast<double>(steps) * scene.dt,
                                    sim.monitors().force_ratio, largest));
    peak.max_speed = std::max(peak.max_speed, history.back().max_speed);
    peak.mean_speed = std::max(peak.mean_speed, history.back().mean_speed);
    const std::string verdict = judge(history, peak, criterion);
    start.moved = verdict == "failed";
    still = verdict == "stable";
    return start.moved || still;
  });
  start.steps = sim.runEquilibrium();
  sim.setStepHook(nullptr);
  start.interrupted = sim.stage() == sim::Stage::kEquilibrium && !start.moved && !still;
  start.reached = sim.equilibriumReached() || still;
  if (!start.interrupted && !start.moved) {
    start.state = sim.checkpoint("", scene.file, "");
    // Every rank restores the fixed and driven bodies, as readCheckpoint gives them to every
    // rank; the checkpoint holds them on rank 0 only.
    if (mpi::rank(comm) != 0) {
      const auto& storage = sim.particles();
      for (std::size_t i = 0; i < storage.localCount(); ++i) {
        if (storage[i].isGlobal()) start.state.particles.push_back(storage[i]);
      }
    }
    if (still) {
      // Stopped by the hook, the stage is still open: end it as runEquilibrium does, the main
      // stage at step 0 and time 0, velocities zeroed when the stage says so.
      start.state.stage = sim::CheckpointStage::kMain;
      start.state.step = 0;
      start.state.time = 0.0;
      start.state.time_digits = ExactSum().digits();
      start.state.equilibrium_steps = start.steps;
      start.state.equilibrium_reached = true;
      if (settle.equilibrium.reset_velocities) {
        for (auto& p : start.state.particles) {
          if (!p.isFree()) continue;
          p.velocity.setZero();
          p.angular_momentum.setZero();
        }
      }
    }
  }
  start.wall_seconds = secondsSince(wall0);
  return start;
}

FosTrial runFosTrial(const setup::Setup& scene, const FosStart& start, double factor,
                     const FosCriterion& criterion, MPI_Comm comm, FosTrialObserver* observer) {
  const auto wall0 = std::chrono::steady_clock::now();
  FosTrial t;
  t.factor = factor;
  if (start.interrupted) {
    t.outcome = "interrupted";
    return t;
  }
  setup::Setup reduced = reduceStrength(scene, factor);
  for (auto& m : reduced.materials) m.local_damping = criterion.local_damping;  // static solution
  reduced.end_time.reset();
  reduced.steps.reset();
  std::unique_ptr<sim::Simulation> simulation =
      start.moved ? std::make_unique<sim::Simulation>(reduced, comm)
                  : std::make_unique<sim::Simulation>(reduced, start.state,
                                                      "the settled state of " + scene.file, comm);
  sim::Simulation& sim = *simulation;
  if (start.moved) {  // from the scene as placed, after its own [equilibrium] if it has one
    sim.setStepHook([comm] { return stopRequested(comm); });
    sim.runEquilibrium();
    sim.setStepHook(nullptr);
  }
  const TrialMeter meter(sim, criterion.label_prefix);
  bool interrupted = stopRequested(comm);
  const double t0 = sim.time();
  Peaks peak;
  const auto sample = [&] {
    const double ratio = sim.monitors().force_ratio;  // the same on every rank
    const FosSample s = meter.measure(sim, sim.time() - t0, ratio, t.max_displacement);
    t.history.push_back(s);
    peak.max_speed = std::max(peak.max_speed, s.max_speed);
    peak.mean_speed = std::max(peak.mean_speed, s.mean_speed);
    t.mean_displacement = s.mean_displacement;
    t.mean_speed = s.mean_speed;
    t.max_speed = s.max_speed;
    t.force_ratio = s.force_ratio;
    t.max_move = s.max_move;
    t.time = s.time;
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
  t.wall_seconds = secondsSince(wall0);
  return t;
}

FosTrial runFosTrial(const setup::Setup& scene, double factor, const FosCriterion& criterion,
                     MPI_Comm comm, FosTrialObserver* observer) {
  const FosStart start = settleForFos(scene, criterion, comm);
  return runFosTrial(scene, start, factor, criterion, comm, observer);
}

}  // namespace polydem::run
