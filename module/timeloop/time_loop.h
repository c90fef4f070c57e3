// The per-rank timeloop, in waLBerla's manner: every rank registers the same named functions in
// the same order, and each step calls them in that order, each call timed into a TimingPool.
// run() steps until a stop condition holds (end time, step limit, force ratio, a user callback)
// and says which one stopped it; a progress line is printed every so many steps or wall seconds.
//
// All ranks must stop at the same step, so every value a condition or the progress line is
// computed from must be GLOBAL: the same on every rank (the force ratio and the kinetic energy
// summed over ranks with ExactSum, contacts summed with allreduceSum, ...). The loop checks this:
// after each step the ranks' decisions are compared in one small allreduce, and a disagreement
// throws SimulationError on every rank instead of leaving some ranks waiting in a collective.
// The same allreduce carries rank 0's wall-clock decision to print progress, so that monitor
// callbacks, which may be collective, are called on every rank at the same steps.
#pragma once

#include <mpi.h>

#include <chrono>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "polydem/core/exact_sum.h"
#include "polydem/core/timing_pool.h"
#include "polydem/timeloop/progress.h"

namespace polydem::timeloop {

/// Why run() returned. kNone: it has not run, or it was interrupted by an exception.
enum class StopReason { kNone, kEndTime, kStepLimit, kForceRatio, kUserCondition };

/// "end time", "step limit", "force ratio", "user condition" or "none".
const char* toString(StopReason reason);

class TimeLoop {
 public:
  using Function = std::function<void()>;

  explicit TimeLoop(MPI_Comm comm = MPI_COMM_WORLD);

  // ---- the step ------------------------------------------------------------------------------
  /// Appends a function to every step; names must be unique (they are the timer names).
  void add(const std::string& name, Function function);
  /// Inserts a function into every step just before the step function `before` (throws Error if
  /// there is none); names must be unique.
  void insertBefore(const std::string& before, const std::string& name, Function function);
  /// Appends a function called after every step, once step() and time() count it, so that what
  /// it records of the state the step produced carries that step's number and time (output,
  /// checks). Timed like the step functions; names share their namespace.
  void addObserver(const std::string& name, Function function);
  /// The time step; a function may change it during a step, and the change applies from the
  /// next step on (the step's own functions work with the dt the step started with).
  void setTimeStep(double dt);
  double timeStep() const { return dt_; }
  /// Steps taken and simulated time: the exact sum of all time steps, rounded once (ExactSum),
  /// so 10 steps of 0.1 give t = 1 exactly and no drift accumulates over millions of steps.
  std::int64_t step() const { return step_; }
  double time() const { return time_value_; }
  /// Sets step and time, e.g. after reading a checkpoint. Give the exact sum (exactTime()) to
  /// continue with the same bits as a run that never stopped.
  void restore(std::int64_t step, double time);
  void restore(std::int64_t step, const ExactSum& time);
  const ExactSum& exactTime() const { return time_; }

  // ---- stop conditions -----------------------------------------------------------------------
  // Checked after every step, in this order, the first that holds being the reason reported;
  // before the first step of run() only the end time and the step limit are checked (the others
  // need the forces of a step).
  /// Stop at the first step with t >= t_end - 1e-12 dt: the run covers [0, t_end], its last step
  /// may overshoot t_end by less than dt, and rounding cannot add a step when dt divides t_end.
  void stopAtTime(double t_end);
  /// Stop when step() reaches `steps` (an absolute count, so it survives a restore()).
  void stopAtStep(std::int64_t steps);
  /// Stop when the force ratio (Keissar eq. 3.2) ratio() < threshold; ratio() is called after
  /// every step on every rank and must be global. NaN (no contacts yet) never stops.
  void stopWhenForceRatioBelow(double threshold, std::function<double()> ratio);
  /// Stop when condition() returns true (called after every step on every rank; it must return
  /// the same on every rank). Replaces an earlier user condition.
  void stopWhen(const std::string& name, std::function<bool()> condition);

  // ---- progress and output -------------------------------------------------------------------
  /// Called (on every rank) for each progress line; its values must be global.
  void setMonitor(std::function<Monitor()> monitor);
  /// A progress line every `steps` steps (0: never) and every `wall_seconds` of wall-clock time
  /// as measured on rank 0 (0: never), whichever comes first, and one when run() stops.
  void setProgressInterval(std::int64_t steps, double wall_seconds);
  /// Where rank 0's lines go (progress, stop message, summary); default log::info.
  void setOutput(std::function<void(const std::string&)> output);

  // ---- running -------------------------------------------------------------------------------
  /// One step: each function in order, timed; then step += 1 and t += dt; then the observers.
  void singleStep();
  /// Steps until a stop condition holds and returns it; throws Error if none is set.
  StopReason run();
  StopReason stopReason() const { return reason_; }
  /// E.g. "end time 1 reached at step 4 (t = 1.2)".
  const std::string& stopMessage() const { return stop_message_; }

  // ---- timing --------------------------------------------------------------------------------
  /// The pool the functions are timed into; other code may add its own timers.
  TimingPool& timing() { return timing_; }
  /// Collective: the pool reduced over ranks (min/mean/max, share, per step) as a table, and
  /// the total wall time of run() (max over ranks) with the step rate.
  std::string summary() const;
  /// Collective: summary() written to the output on rank 0.
  void printSummary() const;

 private:
  struct Step {
    std::string name;
    Function function;
  };
  void checkNewName(const std::string& name, const Function& function) const;
  void timed(const Step& s);
  StopReason check(bool after_step);
  std::string describe(StopReason reason) const;
  bool agree(StopReason reason, bool progress_due);
  bool stopCheck(StopReason& reason);  // sets `reason`; returns whether a progress line is due
  void printProgress();
  void emit(const std::string& line) const;
  double wallNow() const;

  MPI_Comm comm_;
  int rank_ = 0;
  std::vector<Step> steps_;
  std::vector<Step> observers_;
  TimingPool timing_;

  double dt_ = 0.0;
  std::int64_t step_ = 0;
  ExactSum time_;
  double time_value_ = 0.0;

  std::optional<double> end_time_;
  std::optional<std::int64_t> step_limit_;
  std::optional<double> ratio_threshold_;
  std::function<double()> ratio_;
  double last_ratio_ = 0.0;
  std::string condition_name_;
  std::function<bool()> condition_;
  StopReason reason_ = StopReason::kNone;
  std::string stop_message_;

  std::function<Monitor()> monitor_;
  std::int64_t progress_steps_ = 0;
  double progress_seconds_ = 0.0;
  std::function<void(const std::string&)> output_;
  std::chrono::steady_clock::time_point origin_ = std::chrono::steady_clock::now();
  double last_line_wall_ = 0.0;
  std::int64_t last_line_step_ = 0;
  double last_line_time_ = 0.0;
  std::int64_t last_printed_step_ = -1;

  double run_seconds_ = 0.0;  // wall time spent in run()
  std::int64_t run_steps_ = 0;
};

}  // namespace polydem::timeloop
