#include "polydem/timeloop/progress.h"

#include <cmath>
#include <cstdio>

namespace polydem::timeloop {

std::string formatDuration(double seconds) {
  if (!std::isfinite(seconds) || seconds < 0.0) return "-";
  const auto total = static_cast<long long>(std::llround(seconds));
  char text[48];
  std::snprintf(text, sizeof text, "%lld:%02lld:%02lld", total / 3600, total / 60 % 60, total % 60);
  return text;
}

std::string formatProgress(const Progress& progress) {
  char text[256];
  std::snprintf(text, sizeof text, "step %lld | t %.4e s | %.0f steps/s",
                static_cast<long long>(progress.step), progress.time, progress.steps_per_second);
  std::string line = text;
  if (progress.eta_seconds) line += " | ETA " + formatDuration(*progress.eta_seconds);
  const Monitor& m = progress.monitor;
  if (m.contacts) {
    std::snprintf(text, sizeof text, " | contacts %lld", static_cast<long long>(*m.contacts));
    line += text;
  }
  if (m.kinetic_energy) {
    std::snprintf(text, sizeof text, " | Ek %.3e J", *m.kinetic_energy);
    line += text;
  }
  if (m.force_ratio) {
    std::snprintf(text, sizeof text, " | R %.2e", *m.force_ratio);
    line += text;
  }
  return line;
}

}  // namespace polydem::timeloop
