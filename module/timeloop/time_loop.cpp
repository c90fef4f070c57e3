#include "polydem/timeloop/time_loop.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <utility>

#include "polydem/core/error.h"
#include "polydem/core/logging.h"
#include "polydem/core/mpi_env.h"
#include "polydem/core/strings.h"

namespace polydem::timeloop {

namespace {

// The end-time rule's allowance for rounding, as a fraction of the time step.
constexpr double kEndTimeSlack = 1e-12;

// Timer names of the loop's own work; the parentheses keep them apart from step functions.
const char* const kStopChecksTimer = "(stop checks)";
const char* const kProgressTimer = "(progress)";

std::string number(double x) {
  char text[32];
  std::snprintf(text, sizeof text, "%.6g", x);
  return text;
}

}  // namespace

const char* toString(StopReason reason) {
  switch (reason) {
    case StopReason::kNone:
      return "none";
    case StopReason::kEndTime:
      return "end time";
    case StopReason::kStepLimit:
      return "step limit";
    case StopReason::kForceRatio:
      return "force ratio";
    case StopReason::kUserCondition:
      return "user condition";
  }
  return "unknown";
}

TimeLoop::TimeLoop(MPI_Comm comm) : comm_(comm), rank_(mpi::rank(comm)) {}

void TimeLoop::add(const std::string& name, Function function) {
  checkNewName(name, function);
  steps_.push_back({name, std::move(function)});
}

void TimeLoop::insertBefore(const std::string& before, const std::string& name, Function function) {
  checkNewName(name, function);
  const auto at = std::find_if(steps_.begin(), steps_.end(),
                               [&before](const Step& s) { return s.name == before; });
  if (at == steps_.end()) {
    throw Error(cat("TimeLoop: no function '", before, "' to insert '", name, "' before"));
  }
  steps_.insert(at, {name, std::move(function)});
}

void TimeLoop::addObserver(const std::string& name, Function function) {
  checkNewName(name, function);
  observers_.push_back({name, std::move(function)});
}

void TimeLoop::checkNewName(const std::string& name, const Function& function) const {
  if (!function) throw Error(cat("TimeLoop: function '", name, "' is empty"));
  for (const auto* list : {&steps_, &observers_}) {
    for (const Step& s : *list) {
      if (s.name == name) throw Error(cat("TimeLoop: function '", name, "' added twice"));
    }
  }
}

void TimeLoop::setTimeStep(double dt) {
  if (!(dt > 0.0) || !std::isfinite(dt)) throw Error(cat("TimeLoop: time step ", dt, " <= 0"));
  dt_ = dt;
}

void TimeLoop::restore(std::int64_t step, double time) {
  ExactSum t;
  t.add(time);
  restore(step, t);
}

void TimeLoop::restore(std::int64_t step, const ExactSum& time) {
  step_ = step;
  time_ = time;
  time_value_ = time_.value();
}

void TimeLoop::stopAtTime(double t_end) {
  if (!std::isfinite(t_end)) throw Error("TimeLoop: end time is not finite");
  end_time_ = t_end;
}

void TimeLoop::stopAtStep(std::int64_t steps) {
  step_limit_ = steps;
}

void TimeLoop::stopWhenForceRatioBelow(double threshold, std::function<double()> ratio) {
  if (!ratio) throw Error("TimeLoop: empty force-ratio callback");
  ratio_threshold_ = threshold;
  ratio_ = std::move(ratio);
}

void TimeLoop::stopWhen(const std::string& name, std::function<bool()> condition) {
  if (!condition) throw Error(cat("TimeLoop: empty stop condition '", name, "'"));
  condition_name_ = name;
  condition_ = std::move(condition);
}

void TimeLoop::setMonitor(std::function<Monitor()> monitor) {
  monitor_ = std::move(monitor);
}

void TimeLoop::setProgressInterval(std::int64_t steps, double wall_seconds) {
  progress_steps_ = std::max<std::int64_t>(steps, 0);
  progress_seconds_ = std::max(wall_seconds, 0.0);
}

void TimeLoop::setOutput(std::function<void(const std::string&)> output) {
  output_ = std::move(output);
}

void TimeLoop::singleStep() {
  if (!(dt_ > 0.0)) throw Error("TimeLoop: no time step set (setTimeStep)");
  const double dt = dt_;  // a function may change dt_: that is for the next step
  for (const Step& s : steps_) timed(s);
  ++step_;
  time_.add(dt);
  time_value_ = time_.value();
  for (const Step& s : observers_) timed(s);
}

// Times the call into the pool under the step's name (not copied: a long name costs no heap
// allocation per step).
void TimeLoop::timed(const Step& s) {
  const auto start = std::chrono::steady_clock::now();
  s.function();
  timing_.add(s.name,
              std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
}

// The first condition that holds, in the documented order. The callbacks are called on every
// check (not skipped when an earlier condition holds) because they may be collective.
StopReason TimeLoop::check(bool after_step) {
  StopReason reason = StopReason::kNone;
  auto first = [&reason](bool holds, StopReason r) {
    if (holds && reason == StopReason::kNone) reason = r;
  };
  first(end_time_ && time_value_ >= *end_time_ - kEndTimeSlack * dt_, StopReason::kEndTime);
  first(step_limit_ && step_ >= *step_limit_, StopReason::kStepLimit);
  if (!after_step) return reason;
  if (ratio_) {
    last_ratio_ = ratio_();
    first(last_ratio_ < *ratio_threshold_, StopReason::kForceRatio);
  }
  if (condition_) first(condition_(), StopReason::kUserCondition);
  return reason;
}

// One allreduce: checks that every rank takes the same decision and returns whether rank 0 (or
// the step count) asks for a progress line.
bool TimeLoop::agree(StopReason reason, bool progress_due) {
  const int code = static_cast<int>(reason);
  int local[3] = {code, -code, progress_due ? 1 : 0};
  int global[3] = {0, 0, 0};
  MPI_Allreduce(local, global, 3, MPI_INT, MPI_MAX, comm_);
  if (global[0] != -global[1]) {
    throw SimulationError(
        cat("TimeLoop: ranks disagree whether to stop after step ", step_, " (",
            toString(static_cast<StopReason>(-global[1])), " vs ",
            toString(static_cast<StopReason>(global[0])),
            "): stop conditions must be computed from global values, the same on every rank"));
  }
  return global[2] != 0;
}

std::string TimeLoop::describe(StopReason reason) const {
  const std::string at = cat(" at step ", step_, " (t = ", number(time_value_), ")");
  switch (reason) {
    case StopReason::kEndTime:
      return "end time " + number(*end_time_) + " reached" + at;
    case StopReason::kStepLimit:
      return "step limit " + std::to_string(*step_limit_) + " reached" + at;
    case StopReason::kForceRatio:
      return "force ratio " + number(last_ratio_) + " < " + number(*ratio_threshold_) + at;
    case StopReason::kUserCondition:
      return "user condition '" + condition_name_ + "' holds" + at;
    case StopReason::kNone:
      break;
  }
  return "not stopped";
}

double TimeLoop::wallNow() const {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - origin_).count();
}

void TimeLoop::emit(const std::string& line) const {
  if (rank_ != 0) return;
  if (output_) {
    output_(line);
  } else {
    log::info(line);
  }
}

// Rates and the time left come from the interval since the previous line (rank 0's clock is the
// one that is printed); the monitor is called on every rank.
void TimeLoop::printProgress() {
  const TimingPool::Scope scope(timing_, kProgressTimer);
  const double now = wallNow();
  const double wall = now - last_line_wall_;
  Progress p;
  p.step = step_;
  p.time = time_value_;
  p.steps_per_second = wall > 0.0 ? static_cast<double>(step_ - last_line_step_) / wall : 0.0;
  if (end_time_ && wall > 0.0 && time_value_ > last_line_time_) {
    const double sim_per_wall = (time_value_ - last_line_time_) / wall;
    p.eta_seconds = std::max(*end_time_ - time_value_, 0.0) / sim_per_wall;
  }
  if (step_limit_ && p.steps_per_second > 0.0) {
    const double left =
        static_cast<double>(std::max<std::int64_t>(*step_limit_ - step_, 0)) / p.steps_per_second;
    p.eta_seconds = p.eta_seconds ? std::min(*p.eta_seconds, left) : left;
  }
  if (monitor_) p.monitor = monitor_();
  emit(formatProgress(p));
  last_line_wall_ = now;
  last_line_step_ = step_;
  last_line_time_ = time_value_;
  last_printed_step_ = step_;
}

// The stop conditions and their agreement, timed as the loop's own row. A condition may do work
// of its own that it times into the pool under its own name (a checkpoint written when due): that
// time is taken off this row.
bool TimeLoop::stopCheck(StopReason& reason) {
  const double nested_before = timing_.totalSeconds();
  const auto start = std::chrono::steady_clock::now();
  reason = check(true);
  const bool by_steps = progress_steps_ > 0 && step_ % progress_steps_ == 0;
  const bool by_wall =
      rank_ == 0 && progress_seconds_ > 0.0 && wallNow() - last_line_wall_ >= progress_seconds_;
  const bool progress = agree(reason, by_steps || by_wall);
  const double nested = timing_.totalSeconds() - nested_before;
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  timing_.add(kStopChecksTimer, std::max(seconds - nested, 0.0));
  return progress;
}

StopReason TimeLoop::run() {
  if (!end_time_ && !step_limit_ && !ratio_ && !condition_) {
    throw Error("TimeLoop::run: no stop condition set");
  }
  const double start = wallNow();
  last_line_wall_ = start;
  last_line_step_ = step_;
  last_line_time_ = time_value_;
  reason_ = StopReason::kNone;
  stop_message_.clear();
  const bool reports = monitor_ || progress_steps_ > 0 || progress_seconds_ > 0.0;

  StopReason reason = check(false);
  agree(reason, false);
  std::int64_t steps = 0;
  while (reason == StopReason::kNone) {
    singleStep();
    ++steps;
    const bool progress = stopCheck(reason);
    const bool final_line = reason != StopReason::kNone && reports && last_printed_step_ != step_;
    if (progress || final_line) printProgress();
  }
  reason_ = reason;
  stop_message_ = describe(reason);
  emit("stopped: " + stop_message_);
  run_seconds_ += wallNow() - start;
  run_steps_ += steps;
  return reason;
}

std::string TimeLoop::summary() const {
  const std::vector<TimingPool::Reduced> rows = timing_.reduce(comm_);
  const double wall = mpi::allreduceMax(run_seconds_, comm_);
  char line[160];
  std::snprintf(line, sizeof line, "total wall time %.3f s for %lld steps (%.1f steps/s)\n", wall,
                static_cast<long long>(run_steps_),
                wall > 0.0 ? static_cast<double>(run_steps_) / wall : 0.0);
  return TimingPool::table(rows, run_steps_) + line;
}

void TimeLoop::printSummary() const {
  const std::string text = summary();
  emit(text.substr(0, text.size() - 1));
}

}  // namespace polydem::timeloop
