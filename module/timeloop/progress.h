// The one-line progress report of a long run: where the run is, how fast it goes, when it will
// end, and the state of the assembly (contacts, kinetic energy, force ratio).
#pragma once

#include <cstdint>
#include <optional>
#include <string>

namespace polydem::timeloop {

/// What a monitor callback reports for the progress line. Every value must be global (the same
/// on every rank, e.g. summed with ExactSum over ranks); a value left empty is not printed.
struct Monitor {
  std::optional<std::int64_t> contacts;
  std::optional<double> kinetic_energy;  // [J]
  std::optional<double> force_ratio;     // Keissar eq. 3.2
};

struct Progress {
  std::int64_t step = 0;
  double time = 0.0;                  // simulated time [s]
  double steps_per_second = 0.0;      // wall-clock rate since the previous line
  std::optional<double> eta_seconds;  // wall-clock time left, when the run has an end
  Monitor monitor;
};

/// E.g. "step 1200 | t 1.2000e-01 s | 845 steps/s | ETA 0:01:23 | contacts 1523 | Ek 3.210e-02 J |
/// R 4.50e-04".
std::string formatProgress(const Progress& progress);

/// A wall-clock duration as h:mm:ss ("0:01:23"), or "-" when not finite or negative.
std::string formatDuration(double seconds);

}  // namespace polydem::timeloop
