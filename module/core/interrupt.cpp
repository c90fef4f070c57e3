#include "polydem/core/interrupt.h"

#include <atomic>
#include <csignal>

#include "polydem/core/strings.h"

namespace polydem {

namespace {

std::atomic<InterruptProbe> g_probe{nullptr};

std::string nameOf(int signal) {
  if (signal == SIGTERM) return "SIGTERM";
  if (signal == SIGINT) return "SIGINT";
  if (signal == SIGUSR1) return "SIGUSR1";
  return cat("signal ", signal);
}

}  // namespace

void setInterruptProbe(InterruptProbe probe) {
  g_probe.store(probe);
}

int interruptSignal() {
  const InterruptProbe probe = g_probe.load();
  return probe ? probe() : 0;
}

std::string interruptMessage(int signal, const std::string& during) {
  return cat("stopped by ", nameOf(signal), " while ", during, "; nothing was written");
}

}  // namespace polydem
