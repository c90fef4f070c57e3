#include "polydem/timeloop/progress.h"

#include <gtest/gtest.h>

#include <limits>

namespace polydem::timeloop {
namespace {

TEST(Progress, Durations) {
  EXPECT_EQ(formatDuration(0.0), "0:00:00");
  EXPECT_EQ(formatDuration(83.4), "0:01:23");
  EXPECT_EQ(formatDuration(2 * 3600 + 5), "2:00:05");
  EXPECT_EQ(formatDuration(100 * 3600 + 59.6), "100:01:00");
  EXPECT_EQ(formatDuration(-1.0), "-");
  EXPECT_EQ(formatDuration(std::numeric_limits<double>::infinity()), "-");
  EXPECT_EQ(formatDuration(std::numeric_limits<double>::quiet_NaN()), "-");
}

TEST(Progress, OneCompactLine) {
  Progress p;
  p.step = 1200;
  p.time = 0.12;
  p.steps_per_second = 845.4;
  p.eta_seconds = 83.0;
  p.monitor.contacts = 1523;
  p.monitor.kinetic_energy = 3.21e-2;
  p.monitor.force_ratio = 4.5e-4;
  EXPECT_EQ(formatProgress(p),
            "step 1200 | t 1.2000e-01 s | 845 steps/s | ETA 0:01:23 | contacts 1523 | "
            "Ek 3.210e-02 J | R 4.50e-04");
}

TEST(Progress, MissingValuesAreLeftOut) {
  Progress p;
  p.step = 3;
  p.time = 1.5;
  p.steps_per_second = 12.0;
  EXPECT_EQ(formatProgress(p), "step 3 | t 1.5000e+00 s | 12 steps/s");
  p.monitor.force_ratio = 1e-5;
  EXPECT_EQ(formatProgress(p), "step 3 | t 1.5000e+00 s | 12 steps/s | R 1.00e-05");
}

}  // namespace
}  // namespace polydem::timeloop
