// One run per output folder (output/output_lock.h): the lock names its holder, a live holder's or
// another host's lock is refused and left as it is, a dead holder's is taken over, and the lock
// is released (and a folder the lock made, if still empty, removed) at the end.
#include "polydem/output/output_lock.h"

#include <gtest/gtest.h>
#include <mpi.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <fstream>
#include <sstream>

#include "polydem/core/error.h"
#include "polydem/core/mpi_env.h"
#include "polydem/core/strings.h"

namespace polydem::output {
namespace {

namespace fs = std::filesystem;

#define EXPECT_CONTAINS(text, part) \
  EXPECT_NE((text).find(part), std::string::npos) << "'" << (part) << "' not in: " << (text)

std::string contents(const fs::path& file) {
  std::ifstream in(file);
  std::ostringstream out;
  out << in.rdbuf();
  return out.str();
}

void writeLock(const fs::path& file, long pid, const std::string& host, long long ticks) {
  std::ofstream(file) << "polydem output lock\npid " << pid << "\nhost " << host << "\nstart_ticks "
                      << ticks << "\nstarted 2026-01-01T00:00:00Z\n";
}

/// The id of a process that has just ended (so that no process has it for a while).
long endedProcessId() {
  const pid_t child = fork();
  if (child == 0) _exit(0);
  waitpid(child, nullptr, 0);
  return child;
}

/// A fresh folder per test on rank 0 (these tests are not collective).
class LockFile : public ::testing::Test {
 protected:
  void SetUp() override {
    if (mpi::rank() != 0) GTEST_SKIP() << "not collective: rank 0 only";
    dir_ = fs::temp_directory_path() / cat("polydem_lock_", getpid());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    lock_ = dir_ / kOutputLockName;
    me_ = thisProcess();
  }
  void TearDown() override {
    if (!dir_.empty()) fs::remove_all(dir_);
  }
  fs::path dir_, lock_;
  LockHolder me_;
};

TEST_F(LockFile, NamesItsHolderAndIsReleased) {
  const LockAttempt a = tryLockOutput(dir_);
  ASSERT_TRUE(a.held) << a.message;
  EXPECT_EQ(a.message, "");
  LockHolder h;
  ASSERT_TRUE(readLockHolder(lock_, h));
  EXPECT_EQ(h.pid, static_cast<long>(getpid()));
  EXPECT_EQ(h.host, me_.host);
  EXPECT_EQ(h.start_ticks, me_.start_ticks);
  EXPECT_GT(h.start_ticks, 0);  // Linux: /proc/self/stat
  // Held: a second attempt (here from the same process) is refused.
  const LockAttempt again = tryLockOutput(dir_);
  EXPECT_FALSE(again.held);
  EXPECT_CONTAINS(again.message, "is in use");
  unlockOutput(dir_);
  EXPECT_FALSE(fs::exists(lock_));
}

TEST_F(LockFile, LiveHolderOnThisHostIsRefusedAndItsLockKept) {
  const long parent = static_cast<long>(getppid());  // runs as long as this test
  writeLock(lock_, parent, me_.host, -1);
  const std::string before = contents(lock_);
  const LockAttempt a = tryLockOutput(dir_);
  EXPECT_FALSE(a.held);
  EXPECT_CONTAINS(a.message, cat("output folder ", dir_.string(), " is in use: ", lock_.string(),
                                 " names process ", parent, " on host ", me_.host));
  EXPECT_CONTAINS(a.message, "which is still running");
  EXPECT_EQ(contents(lock_), before);
  unlockOutput(dir_);  // not this process's: left
  EXPECT_EQ(contents(lock_), before);
}

TEST_F(LockFile, AnotherHostsLockIsRefused) {
  writeLock(lock_, endedProcessId(), me_.host + ".elsewhere", 5);
  const std::string before = contents(lock_);
  const LockAttempt a = tryLockOutput(dir_);
  EXPECT_FALSE(a.held);
  EXPECT_CONTAINS(a.message, "which cannot be checked from host " + me_.host);
  EXPECT_CONTAINS(a.message, "remove " + lock_.string());
  EXPECT_EQ(contents(lock_), before);
}

TEST_F(LockFile, LockOfAProcessThatIsGoneIsTakenOver) {
  const long gone = endedProcessId();
  writeLock(lock_, gone, me_.host, 12345);
  const LockAttempt a = tryLockOutput(dir_);
  ASSERT_TRUE(a.held) << a.message;
  EXPECT_CONTAINS(a.message, cat("took over ", lock_.string(), " from process ", gone, " on host ",
                                 me_.host, ", started 2026-01-01T00:00:00Z, which is gone"));
  LockHolder h;
  ASSERT_TRUE(readLockHolder(lock_, h));
  EXPECT_EQ(h.pid, static_cast<long>(getpid()));
}

TEST_F(LockFile, ProcessIdReusedSinceIsTakenOver) {
  // The id names a running process, but one that started after the holder did (a reboot, or
  // ids wrapped around): the holder is gone.
  writeLock(lock_, static_cast<long>(getppid()), me_.host, 1);
  const LockAttempt a = tryLockOutput(dir_);
  ASSERT_TRUE(a.held) << a.message;
  EXPECT_CONTAINS(a.message, "whose process id now belongs to another process");
}

TEST_F(LockFile, UnreadableLocksAreRefusedAndKept) {
  std::ofstream(lock_) << "";
  const LockAttempt empty = tryLockOutput(dir_);
  EXPECT_FALSE(empty.held);
  EXPECT_CONTAINS(empty.message, lock_.string() + " names no holder");
  EXPECT_TRUE(fs::exists(lock_));
  std::ofstream(lock_) << "polydem output lock\npid x\nhost h\n";
  EXPECT_FALSE(tryLockOutput(dir_).held);
  fs::remove(lock_);
  ASSERT_EQ(mkfifo(lock_.c_str(), 0600), 0);  // never opened: it would block
  const LockAttempt fifo = tryLockOutput(dir_);
  EXPECT_FALSE(fifo.held);
  EXPECT_CONTAINS(fifo.message, lock_.string() + " is a FIFO");
  EXPECT_TRUE(fs::is_fifo(lock_));
}

TEST(OutputLock, HeldForTheLifetimeOnEveryRankCount) {
  std::string base =
      mpi::rank() == 0 ? cat(fs::temp_directory_path().string(), "/polydem_output_lock_", getpid())
                       : std::string();
  std::uint64_t n = base.size();
  MPI_Bcast(&n, 1, MPI_UINT64_T, 0, MPI_COMM_WORLD);
  base.resize(n);
  MPI_Bcast(base.data(), static_cast<int>(n), MPI_CHAR, 0, MPI_COMM_WORLD);
  const fs::path dir = fs::path(base) / "out";
  if (mpi::rank() == 0) fs::remove_all(base);
  MPI_Barrier(MPI_COMM_WORLD);
  {
    OutputLock lock(dir, MPI_COMM_WORLD);
    EXPECT_TRUE(fs::exists(dir / kOutputLockName));
    // A second run into the folder: refused on every rank, with the reason.
    try {
      OutputLock second(dir, MPI_COMM_WORLD);
      ADD_FAILURE() << "a second lock on a held folder";
    } catch (const OutputError& e) {
      EXPECT_CONTAINS(std::string(e.what()), "is in use");
    }
    EXPECT_TRUE(fs::exists(dir / kOutputLockName));  // the first one's lock is kept
    MPI_Barrier(MPI_COMM_WORLD);                     // every rank has looked before the release
  }
  MPI_Barrier(MPI_COMM_WORLD);
  EXPECT_FALSE(fs::exists(dir));  // it made the folder, nothing was written: removed again
  MPI_Barrier(MPI_COMM_WORLD);
  {
    OutputLock lock(dir, MPI_COMM_WORLD);
    if (mpi::rank() == 0) std::ofstream(dir / "summary.json") << "{}";
    MPI_Barrier(MPI_COMM_WORLD);
  }
  MPI_Barrier(MPI_COMM_WORLD);
  EXPECT_TRUE(fs::exists(dir / "summary.json"));
  EXPECT_FALSE(fs::exists(dir / kOutputLockName));
  MPI_Barrier(MPI_COMM_WORLD);
  if (mpi::rank() == 0) fs::remove_all(base);
}

}  // namespace
}  // namespace polydem::output
