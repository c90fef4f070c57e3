#include "polydem/timeloop/time_loop.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "polydem/core/error.h"
#include "polydem/core/exact_sum.h"
#include "polydem/core/mpi_env.h"

namespace polydem::timeloop {
namespace {

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

// A loop whose output lines are collected (on rank 0; the other ranks print nothing).
struct CapturedLoop {
  TimeLoop loop;
  std::vector<std::string> lines;
  CapturedLoop() {
    loop.setOutput([this](const std::string& line) { lines.push_back(line); });
  }
};

TEST(TimeLoop, FunctionsRunInRegistrationOrderAndAreTimed) {
  CapturedLoop c;
  std::vector<std::string> calls;
  const std::vector<std::string> names = {"broadphase", "contact", "integrate"};
  for (const std::string& name : names) c.loop.add(name, [&calls, name] { calls.push_back(name); });
  c.loop.setTimeStep(0.5);
  c.loop.singleStep();
  c.loop.singleStep();
  EXPECT_EQ(calls, (std::vector<std::string>{"broadphase", "contact", "integrate", "broadphase",
                                             "contact", "integrate"}));
  EXPECT_EQ(c.loop.step(), 2);
  EXPECT_EQ(c.loop.time(), 1.0);

  const auto& entries = c.loop.timing().entries();
  ASSERT_EQ(entries.size(), names.size());
  for (std::size_t i = 0; i < names.size(); ++i) {
    EXPECT_EQ(entries[i].name, names[i]);
    EXPECT_EQ(entries[i].count, 2);
  }
  const auto rows = c.loop.timing().reduce(MPI_COMM_WORLD);
  ASSERT_EQ(rows.size(), names.size());
  for (std::size_t i = 0; i < names.size(); ++i) EXPECT_EQ(rows[i].name, names[i]);
}

TEST(TimeLoop, MisuseIsAnError) {
  TimeLoop loop;
  loop.add("a", [] {});
  EXPECT_THROW(loop.add("a", [] {}), Error);
  EXPECT_THROW(loop.singleStep(), Error);  // no time step yet
  EXPECT_THROW(loop.setTimeStep(0.0), Error);
  EXPECT_THROW(loop.setTimeStep(std::numeric_limits<double>::quiet_NaN()), Error);
  loop.setTimeStep(1.0);
  EXPECT_THROW(loop.run(), Error);  // no stop condition
  EXPECT_EQ(loop.stopReason(), StopReason::kNone);
}

TEST(TimeLoop, StepLimit) {
  CapturedLoop c;
  int calls = 0;
  c.loop.add("count", [&calls] { ++calls; });
  c.loop.setTimeStep(1e-3);
  c.loop.stopAtStep(7);
  EXPECT_EQ(c.loop.run(), StopReason::kStepLimit);
  EXPECT_EQ(c.loop.step(), 7);
  EXPECT_EQ(calls, 7);
  EXPECT_TRUE(contains(c.loop.stopMessage(), "step limit 7 reached at step 7"));
  // Already at the limit: a second run takes no step.
  EXPECT_EQ(c.loop.run(), StopReason::kStepLimit);
  EXPECT_EQ(calls, 7);
  if (mpi::rank() == 0) {
    ASSERT_EQ(c.lines.size(), 2u);
    EXPECT_EQ(c.lines[0], "stopped: " + c.loop.stopMessage());
  } else {
    EXPECT_TRUE(c.lines.empty());
  }
}

// The end-time rule: stop at the first step with t >= t_end - 1e-12 dt.
std::int64_t stepsToReach(double t_end, double dt) {
  TimeLoop loop;
  loop.setOutput([](const std::string&) {});
  loop.add("nothing", [] {});
  loop.setTimeStep(dt);
  loop.stopAtTime(t_end);
  EXPECT_EQ(loop.run(), StopReason::kEndTime);
  return loop.step();
}

TEST(TimeLoop, EndTimeRule) {
  // dt does not divide t_end: t = 0.3, 0.6, 0.9 < 1, then 1.2 >= 1, so ceil(1 / 0.3) = 4 steps
  // and the last one overshoots.
  EXPECT_EQ(stepsToReach(1.0, 0.3), 4);
  EXPECT_EQ(stepsToReach(1.0, 0.4), 3);
  // dt divides t_end: exactly t_end / dt steps, although 0.1 is not a binary fraction (ten
  // additions of 0.1 give 0.9999999999999999 in plain floating point).
  EXPECT_EQ(stepsToReach(1.0, 0.1), 10);
  EXPECT_EQ(stepsToReach(1.0, 0.25), 4);
  EXPECT_EQ(stepsToReach(3.0, 1e-3), 3000);
  // In general: the last step starts before t_end and ends at or after it.
  for (double dt : {0.07, 0.013, 0.33, 1.7}) {
    const double n = static_cast<double>(stepsToReach(1.0, dt));
    EXPECT_LT((n - 1.0) * dt, 1.0 - 1e-12 * dt) << dt;
    EXPECT_GE(n * dt, 1.0 - 1e-12 * dt) << dt;
  }
}

TEST(TimeLoop, TimeIsTheExactSumOfChangingTimeSteps) {
  // A function raises dt during step 3; the step still advances by the old dt, so t goes
  // 0.1, 0.2, 0.3, 0.5, 0.7, 0.9, 1.1 and the run stops after 7 steps.
  CapturedLoop c;
  c.loop.setTimeStep(0.1);
  c.loop.add("adapt", [&c] {
    if (c.loop.step() == 2) c.loop.setTimeStep(0.2);
  });
  c.loop.stopAtTime(1.0);
  EXPECT_EQ(c.loop.run(), StopReason::kEndTime);
  EXPECT_EQ(c.loop.step(), 7);
  ExactSum expected;
  for (double dt : {0.1, 0.1, 0.1, 0.2, 0.2, 0.2, 0.2}) expected.add(dt);
  EXPECT_EQ(c.loop.time(), expected.value());
  EXPECT_TRUE(contains(c.loop.stopMessage(), "end time 1 reached at step 7 (t = 1.1)"));
}

TEST(TimeLoop, EndTimeAlreadyReachedTakesNoStep) {
  CapturedLoop c;
  int calls = 0;
  c.loop.add("count", [&calls] { ++calls; });
  c.loop.setTimeStep(0.1);
  c.loop.restore(20, 2.0);
  c.loop.stopAtTime(1.0);
  EXPECT_EQ(c.loop.run(), StopReason::kEndTime);
  EXPECT_EQ(calls, 0);
  EXPECT_EQ(c.loop.step(), 20);
}

TEST(TimeLoop, ForceRatioFromAGlobalSum) {
  // Each rank holds its share of R = 1 / (1 + step); the callback sums the shares over ranks
  // (a collective, as a real force-ratio monitor is). R < 0.1 first after step 10.
  CapturedLoop c;
  c.loop.add("nothing", [] {});
  c.loop.setTimeStep(1.0);
  int calls = 0;
  c.loop.stopWhenForceRatioBelow(0.1, [&c, &calls] {
    ++calls;
    ExactSum r;
    r.add(1.0 / (1.0 + static_cast<double>(c.loop.step())) / mpi::size());
    r.allreduce(MPI_COMM_WORLD);
    return r.value();
  });
  EXPECT_EQ(c.loop.run(), StopReason::kForceRatio);
  EXPECT_EQ(c.loop.step(), 10);
  EXPECT_EQ(calls, 10);  // after every step, never before the first
  EXPECT_TRUE(contains(c.loop.stopMessage(), "force ratio 0.0909091 < 0.1 at step 10"));
}

TEST(TimeLoop, ForceRatioNaNDoesNotStop) {
  CapturedLoop c;
  c.loop.add("nothing", [] {});
  c.loop.setTimeStep(1.0);
  c.loop.stopAtStep(5);
  c.loop.stopWhenForceRatioBelow(1.0, [] { return std::numeric_limits<double>::quiet_NaN(); });
  EXPECT_EQ(c.loop.run(), StopReason::kStepLimit);
  EXPECT_EQ(c.loop.step(), 5);
}

TEST(TimeLoop, UserCondition) {
  CapturedLoop c;
  c.loop.add("nothing", [] {});
  c.loop.setTimeStep(1.0);
  c.loop.stopWhen("slope moved 1 m", [&c] { return c.loop.step() == 5; });
  EXPECT_EQ(c.loop.run(), StopReason::kUserCondition);
  EXPECT_EQ(c.loop.step(), 5);
  EXPECT_EQ(std::string(toString(c.loop.stopReason())), "user condition");
  EXPECT_TRUE(contains(c.loop.stopMessage(), "user condition 'slope moved 1 m' holds at step 5"));
}

TEST(TimeLoop, FirstConditionInOrderIsReported) {
  // End time, step limit, force ratio and user condition all hold after step 4: the end time
  // is reported; without it the step limit, and so on.
  for (int dropped = 0; dropped < 4; ++dropped) {
    CapturedLoop c;
    c.loop.add("nothing", [] {});
    c.loop.setTimeStep(0.25);
    if (dropped < 1) c.loop.stopAtTime(1.0);
    if (dropped < 2) c.loop.stopAtStep(4);
    if (dropped < 3) {
      c.loop.stopWhenForceRatioBelow(1.0, [&c] { return c.loop.step() >= 4 ? 0.5 : 2.0; });
    }
    c.loop.stopWhen("four", [&c] { return c.loop.step() >= 4; });
    const StopReason expected[] = {StopReason::kEndTime, StopReason::kStepLimit,
                                   StopReason::kForceRatio, StopReason::kUserCondition};
    EXPECT_EQ(c.loop.run(), expected[dropped]);
    EXPECT_EQ(c.loop.step(), 4);
  }
}

TEST(TimeLoop, RanksThatDisagreeThrowInsteadOfHanging) {
  if (mpi::size() < 2) GTEST_SKIP() << "needs 2 ranks";
  CapturedLoop c;
  c.loop.add("nothing", [] {});
  c.loop.setTimeStep(1.0);
  c.loop.stopAtStep(10);
  c.loop.stopWhen("rank 1 only", [&c] { return mpi::rank() == 1 && c.loop.step() == 3; });
  EXPECT_THROW(c.loop.run(), SimulationError);
  EXPECT_EQ(c.loop.step(), 3);
}

TEST(TimeLoop, ProgressLineEveryNSteps) {
  CapturedLoop c;
  c.loop.add("nothing", [] {});
  c.loop.setTimeStep(1e-3);
  c.loop.stopAtStep(30);
  int monitor_calls = 0;
  c.loop.setMonitor([&monitor_calls] {
    ++monitor_calls;
    Monitor m;
    m.contacts = mpi::allreduceSum(21) * 2 / mpi::size();  // a global value: 42
    m.kinetic_energy = 1.5;
    m.force_ratio = 2e-3;
    return m;
  });
  c.loop.setProgressInterval(10, 0.0);
  EXPECT_EQ(c.loop.run(), StopReason::kStepLimit);
  EXPECT_EQ(monitor_calls, 3);  // steps 10, 20, 30; the last is not repeated at the stop
  if (mpi::rank() != 0) {
    EXPECT_TRUE(c.lines.empty());
    return;
  }
  ASSERT_EQ(c.lines.size(), 4u);
  const char* const times[] = {"1.0000e-02", "2.0000e-02", "3.0000e-02"};
  for (int i = 0; i < 3; ++i) {
    const std::string& line = c.lines[i];
    EXPECT_EQ(line.rfind("step " + std::to_string(10 * (i + 1)) + " | t " + times[i] + " s | ", 0),
              0u)
        << line;
    EXPECT_TRUE(contains(line, " steps/s | ETA ")) << line;
    EXPECT_TRUE(contains(line, " | contacts 42 | Ek 1.500e+00 J | R 2.00e-03")) << line;
    EXPECT_EQ(line.find('\n'), std::string::npos);
  }
  EXPECT_TRUE(contains(c.lines[2], "ETA 0:00:00"));  // nothing left at the step limit
  EXPECT_EQ(c.lines[3], "stopped: step limit 30 reached at step 30 (t = 0.03)");
}

TEST(TimeLoop, ProgressByWallClockIsDecidedOnRankZeroForAll) {
  // A progress line whenever rank 0's clock has advanced (every step, in practice). The monitor
  // is collective: were it called on some ranks only, this test would hang.
  CapturedLoop c;
  c.loop.add("nothing", [] {});
  c.loop.setTimeStep(1.0);
  c.loop.stopAtStep(20);
  std::int64_t monitor_calls = 0;
  c.loop.setMonitor([&monitor_calls] {
    ++monitor_calls;
    Monitor m;
    m.contacts = mpi::allreduceSum(1);
    return m;
  });
  c.loop.setProgressInterval(0, 1e-9);
  c.loop.run();
  EXPECT_GE(monitor_calls, 1);
  EXPECT_EQ(mpi::allreduceSum(monitor_calls), monitor_calls * mpi::size());
  if (mpi::rank() == 0) {
    EXPECT_EQ(static_cast<std::int64_t>(c.lines.size()), monitor_calls + 1);
    EXPECT_TRUE(contains(c.lines.front(), "contacts " + std::to_string(mpi::size())));
  }
}

TEST(TimeLoop, FinalLineAndSummary) {
  CapturedLoop c;
  c.loop.add("broadphase", [] {});
  c.loop.add("contact", [] {});
  c.loop.setTimeStep(0.5);
  c.loop.stopAtTime(2.5);
  c.loop.setMonitor([] { return Monitor{}; });
  EXPECT_EQ(c.loop.run(), StopReason::kEndTime);
  const std::string summary = c.loop.summary();
  for (const char* name : {"broadphase", "contact", "(stop checks)", "(progress)"}) {
    EXPECT_TRUE(contains(summary, name)) << summary;
  }
  EXPECT_TRUE(contains(summary, "total wall time")) << summary;
  EXPECT_TRUE(contains(summary, "for 5 steps")) << summary;
  c.loop.printSummary();
  if (mpi::rank() == 0) {
    // One progress line at the stop (a monitor is set, no interval), the stop line, the summary.
    ASSERT_EQ(c.lines.size(), 3u);
    EXPECT_EQ(c.lines[0].rfind("step 5 | t 2.5000e+00 s | ", 0), 0u) << c.lines[0];
    EXPECT_EQ(c.lines[1], "stopped: end time 2.5 reached at step 5 (t = 2.5)");
    EXPECT_EQ(c.lines[2] + "\n", summary);
  }
}

// Work a stop condition times into the pool under its own name (a checkpoint written when due) is
// that row's, not the stop check's: a condition that reports 1e6 s of its own leaves nothing in
// "(stop checks)" (without the deduction the row would hold the check's own, non-zero, time).
TEST(TimeLoop, WorkTimedInsideTheStopCheckIsNotCountedTwice) {
  CapturedLoop c;
  c.loop.add("step", [] {});
  c.loop.setTimeStep(0.5);
  c.loop.stopAtStep(3);
  int calls = 0;
  c.loop.stopWhen("writer", [&] {
    c.loop.timing().add("(checkpoint)", 1e6);
    ++calls;
    return false;
  });
  EXPECT_EQ(c.loop.run(), StopReason::kStepLimit);
  EXPECT_EQ(calls, 3);
  EXPECT_EQ(c.loop.timing().seconds("(checkpoint)"), 3e6);
  EXPECT_EQ(c.loop.timing().seconds("(stop checks)"), 0.0);
  const auto& rows = c.loop.timing().entries();
  const auto row = std::find_if(rows.begin(), rows.end(),
                                [](const auto& e) { return e.name == "(stop checks)"; });
  ASSERT_NE(row, rows.end());
  EXPECT_EQ(row->count, 3);
}

}  // namespace
}  // namespace polydem::timeloop
