// One run per output folder: a run holds DIR/polydem.lock while it writes into DIR, so that a
// second run into the same folder is refused instead of mixing its files with the first's (and
// pruning its checkpoints). The file names the holder (pid, host, start), so that a lock left by a
// run that was killed (kill -9, SIGINT, a crash, MPI_Abort) is recognised as stale on the same
// host and taken over with a warning. See docs/checkpoint.md, 'One run per output folder'.
#pragma once

#include <mpi.h>

#include <filesystem>
#include <string>

namespace polydem::output {

inline constexpr const char* kOutputLockName = "polydem.lock";

/// Who holds a lock, as its file says.
struct LockHolder {
  long pid = 0;
  std::string host;
  long long start_ticks = -1;  // the process's start time (/proc/<pid>/stat), -1: unknown
  std::string started;         // UTC, ISO 8601, for messages
};

/// The outcome of tryLockOutput: held (a stale lock may have been taken over), or refused.
struct LockAttempt {
  bool held = false;
  std::string message;  // refused: why (names the file and the holder); held: a takeover, or ""
};

/// Takes `dir`/polydem.lock for this process (not collective; `dir` must exist). Refused when the
/// file names a process that still runs on this host, a process on another host (which this
/// host cannot check), or cannot be read; a lock of a process that is gone from this host (or
/// whose id now belongs to a process started later) is taken over.
LockAttempt tryLockOutput(const std::filesystem::path& dir);
/// Removes `dir`/polydem.lock if it names this process; any other file is left (not collective).
void unlockOutput(const std::filesystem::path& dir);
/// The holder a lock file names; false if it cannot be read or names no holder.
bool readLockHolder(const std::filesystem::path& file, LockHolder& holder);
/// This process as a lock names it.
LockHolder thisProcess();

/// DIR/polydem.lock held by rank 0 for the lifetime of the object (collective construction).
class OutputLock {
 public:
  /// Creates `dir` if missing and takes its lock on rank 0; if that is refused, throws
  /// OutputError with the reason on every rank (the folder and its files are left as they were).
  OutputLock(const std::filesystem::path& dir, MPI_Comm comm);
  /// Releases the lock (rank 0, not collective: it also runs while an exception unwinds), and
  /// removes `dir` again if this lock created it and nothing was written into it.
  ~OutputLock();
  OutputLock(const OutputLock&) = delete;
  OutputLock& operator=(const OutputLock&) = delete;

 private:
  std::filesystem::path dir_;
  bool held_ = false;
  bool created_dir_ = false;
};

}  // namespace polydem::output
