// Long set-up work that no checkpoint can save (cutting a rock mass, building the shapes' hulls)
// asks here, every so often, whether the process has been asked to stop. The program that
// catches the signals (polydem run: run/run_checkpoint.h) installs the probe; without one,
// nothing is ever interrupted (Python, tests, C++ programs).
#pragma once

#include <string>

#include "polydem/core/error.h"

namespace polydem {

/// A stop signal came during set-up work: the message says which signal and what was under way.
/// Nothing has been written; the program exits non-zero.
class Interrupted : public Error {
 public:
  using Error::Error;
};

/// The signal number received so far, or 0 (async-signal-safe read of a flag).
using InterruptProbe = int (*)();

/// Installs `probe` for the whole process (nullptr: none). Idempotent.
void setInterruptProbe(InterruptProbe probe);

/// The signal the probe reports, or 0.
int interruptSignal();

/// "stopped by SIGTERM while <during>; nothing was written".
std::string interruptMessage(int signal, const std::string& during);

/// Throws Interrupted("stopped by SIGTERM while <during>; nothing was written") if the probe
/// reports a signal. `during` is built only then (a callable returning the text), so that a loop
/// may ask at every turn.
template <typename During>
void throwIfInterrupted(const During& during) {
  if (const int signal = interruptSignal(); signal != 0) {
    throw Interrupted(interruptMessage(signal, during()));
  }
}

}  // namespace polydem
