// Writing: the temporary file is renamed only when complete, a failure on any rank fails on every
// rank and leaves the previous checkpoint intact; file names with run ids and keeping the last K of
// one run.
#include <gtest/gtest.h>
#include <mpi.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <fstream>
#include <functional>
#include <set>
#include <sstream>

#include "checkpoint_test_data.h"
#include "polydem/checkpoint/checkpoint.h"
#include "polydem/core/error.h"
#include "polydem/core/mpi_env.h"

namespace polydem::checkpoint {
namespace {

namespace fs = std::filesystem;

using testing::readBytes;

/// Names of the entries of `dir`, sorted.
std::vector<std::string> entries(const fs::path& dir) {
  std::vector<std::string> out;
  for (const auto& e : fs::directory_iterator(dir)) out.push_back(e.path().filename().string());
  std::sort(out.begin(), out.end());
  return out;
}

class CheckpointWrite : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = testing::scratchDirectory("checkpoint_write", MPI_COMM_WORLD);
    path_ = dir_ / "run.h5";
    old_ = testing::makeTruth(20, 30, true, 1);
    writeCheckpoint(path_, testing::shareOf(old_, mpi::rank(), mpi::size()), MPI_COMM_WORLD);
    old_bytes_ = readBytes(path_);
  }
  void TearDown() override {
    MPI_Barrier(MPI_COMM_WORLD);
    if (mpi::rank() == 0) fs::remove_all(dir_);
  }

  /// The previous checkpoint is still there, unchanged, and no temporary file is left.
  void expectPreviousIntact() {
    MPI_Barrier(MPI_COMM_WORLD);
    EXPECT_EQ(readBytes(path_), old_bytes_);
    EXPECT_EQ(entries(dir_), std::vector<std::string>{"run.h5"});
    const sim::CheckpointData read = readCheckpoint(path_, MPI_COMM_WORLD);
    EXPECT_EQ(testing::gatherFree(read, MPI_COMM_WORLD).size(), old_.free.size());
  }

  std::string failureOf(const std::function<void()>& write) {
    try {
      write();
    } catch (const CheckpointError& e) {
      return e.what();
    }
    ADD_FAILURE() << "the write did not fail";
    return {};
  }

  fs::path dir_, path_;
  testing::Truth old_;
  std::string old_bytes_;
};

TEST_F(CheckpointWrite, ReplacesThePreviousFileAndLeavesNoTemporary) {
  const auto next = testing::makeTruth(25, 40, true, 2);
  writeCheckpoint(path_, testing::shareOf(next, mpi::rank(), mpi::size()), MPI_COMM_WORLD);
  MPI_Barrier(MPI_COMM_WORLD);
  EXPECT_EQ(entries(dir_), std::vector<std::string>{"run.h5"});
  const CheckpointSummary s = verifyCheckpoint(path_, MPI_COMM_WORLD);
  EXPECT_EQ(s.particles, static_cast<std::int64_t>(next.free.size() + next.globals.size()));
}

TEST_F(CheckpointWrite, NoRoomLeavesThePreviousCheckpoint) {
  // A file size limit below the checkpoint's size, as a nearly full disk: the write is refused
  // on every rank before it starts (the limit is set on the last rank only).
  const auto big = testing::makeTruth(3000, 6000, true, 3);
  const sim::CheckpointData share = testing::shareOf(big, mpi::rank(), mpi::size());
  rlimit saved{};
  getrlimit(RLIMIT_FSIZE, &saved);
  const auto saved_handler = signal(SIGXFSZ, SIG_IGN);
  if (mpi::rank() == mpi::size() - 1) {
    rlimit small = saved;
    small.rlim_cur = 64 * 1024;
    setrlimit(RLIMIT_FSIZE, &small);
  }
  const std::string message = failureOf([&] { writeCheckpoint(path_, share, MPI_COMM_WORLD); });
  setrlimit(RLIMIT_FSIZE, &saved);
  signal(SIGXFSZ, saved_handler);
  EXPECT_NE(message.find(path_.string() + ": needs about"), std::string::npos) << message;
  EXPECT_NE(message.find("file size limit of 65536 bytes"), std::string::npos) << message;
  expectPreviousIntact();
}

TEST_F(CheckpointWrite, InvalidDataOnOneRankFailsOnEveryRank) {
  sim::CheckpointData share = testing::shareOf(old_, mpi::rank(), mpi::size());
  if (mpi::rank() == mpi::size() - 1) {
    share.particles.push_back(old_.free.front());
    share.particles.back().flags |= particles::kGhost;
  }
  const std::string message = failureOf([&] { writeCheckpoint(path_, share, MPI_COMM_WORLD); });
  EXPECT_NE(message.find("is a ghost copy"), std::string::npos) << message;
  expectPreviousIntact();
}

TEST_F(CheckpointWrite, InconsistentTimeIsRefused) {
  sim::CheckpointData share = testing::shareOf(old_, mpi::rank(), mpi::size());
  share.time = std::nextafter(share.time, 1e9);
  const std::string message = failureOf([&] { writeCheckpoint(path_, share, MPI_COMM_WORLD); });
  EXPECT_NE(message.find("is not the rounded exact time"), std::string::npos) << message;
  expectPreviousIntact();
}

TEST_F(CheckpointWrite, DirectoryTargetIsRefusedBeforeAnyFileIsMade) {
  // A rename onto a directory would fail after the whole write; the target is checked first.
  const fs::path target = dir_ / "occupied";
  if (mpi::rank() == 0) {
    fs::create_directory(target);
    std::ofstream(target / "keep.txt") << "keep";
  }
  MPI_Barrier(MPI_COMM_WORLD);
  const sim::CheckpointData share = testing::shareOf(old_, mpi::rank(), mpi::size());
  const std::string message = failureOf([&] { writeCheckpoint(target, share, MPI_COMM_WORLD); });
  EXPECT_NE(message.find("checkpoint " + target.string() + ": is a directory"), std::string::npos)
      << message;
  MPI_Barrier(MPI_COMM_WORLD);
  EXPECT_EQ(entries(dir_), (std::vector<std::string>{"occupied", "run.h5"}));
  EXPECT_EQ(entries(target), std::vector<std::string>{"keep.txt"});
}

TEST_F(CheckpointWrite, MissingDirectory) {
  const sim::CheckpointData share = testing::shareOf(old_, mpi::rank(), mpi::size());
  const fs::path path = dir_ / "absent" / "run.h5";
  const std::string message = failureOf([&] { writeCheckpoint(path, share, MPI_COMM_WORLD); });
  EXPECT_NE(message.find("cannot create the file"), std::string::npos) << message;
  expectPreviousIntact();
}

TEST(CheckpointFiles, NamesListAndKeepLastOfOneRun) {
  if (mpi::rank() != 0) return;  // not collective
  const fs::path dir = fs::temp_directory_path() / ("polydem_ckfiles_" + std::to_string(getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string run = "0badcafe", other = "12345678";
  EXPECT_EQ(checkpointFileName(dir, 1500, run), dir / "checkpoint_000000001500_0badcafe.h5");
  EXPECT_EQ(checkpointFileName("", 0, run).string(), "checkpoint_000000000000_0badcafe.h5");
  EXPECT_THROW(checkpointFileName(dir, -1, run), Error);
  for (const std::string bad : {"", "0BADCAFE", "0badcafe0", "0badcaf", "0badcafg"}) {
    EXPECT_THROW(checkpointFileName(dir, 1, bad), Error) << bad;
  }
  EXPECT_TRUE(listCheckpoints(dir / "absent").empty());

  for (std::int64_t step : {100, 0, 1500, 5, 10})
    std::ofstream(checkpointFileName(dir, step, run)) << step;
  // Another run's checkpoints, among them steps of the same numbers, and one named before runs had
  // ids: none of them is this run's to prune.
  for (std::int64_t step : {0, 5, 2000}) std::ofstream(checkpointFileName(dir, step, other)) << 1;
  std::ofstream(dir / "checkpoint_000000000001.h5") << "older polydem";
  // Names that only look like checkpoints, a directory with a checkpoint's name, and a link.
  const std::vector<std::string> others = {"checkpoint_000000000005_0badcafe.h5.tmp.4242",
                                           "checkpoint_5.h5",
                                           "checkpoint_00000000001x.h5",
                                           "checkpoint_000000000007_0badcafe.h5.bak",
                                           "checkpoint_000000000007-0badcafe.h5",
                                           "checkpoint_000000000007_0badcafe0.h5",
                                           "notes.txt",
                                           "Checkpoint_000000000003_0badcafe.h5"};
  for (const auto& name : others) std::ofstream(dir / name) << "x";
  fs::create_directory(checkpointFileName(dir, 200, run));
  fs::create_symlink("notes.txt", checkpointFileName(dir, 1, run));

  const auto listed = listCheckpoints(dir);
  std::vector<std::pair<std::int64_t, std::string>> found;
  for (const auto& f : listed) found.emplace_back(f.step, f.run_id);
  EXPECT_EQ(found, (std::vector<std::pair<std::int64_t, std::string>>{{0, run},
                                                                      {0, other},
                                                                      {1, ""},
                                                                      {5, run},
                                                                      {5, other},
                                                                      {10, run},
                                                                      {100, run},
                                                                      {1500, run},
                                                                      {2000, other}}));

  const auto deleted = pruneCheckpoints(dir, run, 2);
  EXPECT_EQ(deleted,
            (std::vector<fs::path>{checkpointFileName(dir, 0, run), checkpointFileName(dir, 5, run),
                                   checkpointFileName(dir, 10, run)}));
  std::vector<std::string> expected = others;
  for (const auto& f : {checkpointFileName(dir, 100, run), checkpointFileName(dir, 200, run),
                        checkpointFileName(dir, 1500, run), checkpointFileName(dir, 1, run),
                        checkpointFileName(dir, 0, other), checkpointFileName(dir, 5, other),
                        checkpointFileName(dir, 2000, other)}) {
    expected.push_back(f.filename().string());
  }
  expected.push_back("checkpoint_000000000001.h5");
  std::sort(expected.begin(), expected.end());
  EXPECT_EQ(entries(dir), expected);
  EXPECT_TRUE(pruneCheckpoints(dir, run, 2).empty());
  EXPECT_EQ(pruneCheckpoints(dir, run, 1).size(), 1u);
  EXPECT_TRUE(fs::exists(checkpointFileName(dir, 1500, run)));
  EXPECT_TRUE(fs::exists(checkpointFileName(dir, 0, other)));  // the other run's oldest
  EXPECT_THROW(pruneCheckpoints(dir, run, 0), Error);
  EXPECT_THROW(pruneCheckpoints(dir, "", 1), Error);  // the pre-id files have no run to prune
  fs::remove_all(dir);
}

TEST(CheckpointFiles, NewRunIdsAvoidTheIdsInTheFolder) {
  if (mpi::rank() != 0) return;  // not collective
  const fs::path dir = fs::temp_directory_path() / ("polydem_ckids_" + std::to_string(getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::set<std::string> ids;
  for (int i = 0; i < 20; ++i) {
    const std::string id = newCheckpointRunId(dir);
    EXPECT_NO_THROW(checkpointFileName(dir, i, id)) << id;  // a well-formed id
    EXPECT_FALSE(ids.contains(id)) << id;
    ids.insert(id);
    // The next one must avoid it: its file, or a temporary file of it, is in the folder.
    const fs::path file = checkpointFileName(dir, i, id);
    std::ofstream(i % 2 == 0 ? file : fs::path(file.string() + ".tmp.1")) << "x";
  }
  EXPECT_EQ(newCheckpointRunId(dir / "absent").size(), 8u);
  fs::remove_all(dir);
}

/// The id of a process that has just ended (so that no process has it for a while).
long endedProcessId() {
  const pid_t child = fork();
  if (child == 0) _exit(0);
  waitpid(child, nullptr, 0);
  return child;
}

TEST(CheckpointFiles, StaleTemporaryFilesOnlyOfPolydemsNaming) {
  if (mpi::rank() != 0) return;  // not collective
  const fs::path dir = fs::temp_directory_path() / ("polydem_cktmp_" + std::to_string(getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string base = checkpointFileName("", 50, "0badcafe").string();
  const long gone = endedProcessId();
  const std::string stale = base + ".tmp." + std::to_string(gone);
  const std::string alive = base + ".tmp." + std::to_string(getppid());
  std::ofstream(dir / stale) << "half a checkpoint";
  std::ofstream(dir / alive) << "being written";
  // Names that are not polydem's temporary files, and a directory with such a name.
  const std::vector<std::string> others = {base + ".tmp." + std::to_string(gone) + "x",
                                           base + ".tmp.",
                                           "checkpoint_50.h5.tmp." + std::to_string(gone),
                                           "checkpoint_000000000050.h5.tmp.x1",
                                           "notes.tmp." + std::to_string(gone),
                                           base,
                                           base + ".bak.tmp." + std::to_string(gone)};
  for (const auto& name : others) std::ofstream(dir / name) << "keep";
  fs::create_directory(dir / (base + ".tmp.1"));

  const auto listed = listTemporaryCheckpoints(dir);
  ASSERT_EQ(listed.size(), 2u);
  const auto removed = removeStaleTemporaryCheckpoints(dir);
  ASSERT_EQ(removed.size(), 2u);
  for (const auto& t : removed) {
    EXPECT_EQ(t.removed, t.path.filename() == stale) << t.path;
    EXPECT_EQ(t.writer_alive, t.path.filename() == alive) << t.path;
    if (t.path.filename() == stale) {
      EXPECT_EQ(t.bytes, 17u);
    }
  }
  std::vector<std::string> expected = others;
  expected.push_back(alive);
  expected.push_back(base + ".tmp.1");
  std::sort(expected.begin(), expected.end());
  EXPECT_EQ(entries(dir), expected);
  EXPECT_TRUE(removeStaleTemporaryCheckpoints(dir / "absent").empty());
  fs::remove_all(dir);
}

}  // namespace
}  // namespace polydem::checkpoint
