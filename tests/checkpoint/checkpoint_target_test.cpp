// What writeCheckpoint may write over (checkpointTarget): a new path, an empty file or a polydem
// checkpoint (a symbolic link followed to one); a FIFO, a device, a directory, an unrelated file
// or a link to any of them is refused on every rank with the path and what it is, and left as it
// was, with no temporary file made.
#include <gtest/gtest.h>
#include <hdf5.h>
#include <mpi.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <unistd.h>

#include <fstream>
#include <functional>
#include <sstream>

#include "checkpoint_test_data.h"
#include "polydem/checkpoint/checkpoint.h"
#include "polydem/core/error.h"
#include "polydem/core/mpi_env.h"

namespace polydem::checkpoint {
namespace {

namespace fs = std::filesystem;

std::vector<std::string> entries(const fs::path& dir) {
  std::vector<std::string> out;
  for (const auto& e : fs::directory_iterator(dir)) out.push_back(e.path().filename().string());
  std::sort(out.begin(), out.end());
  return out;
}

class CheckpointTarget : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = testing::scratchDirectory("checkpoint_target", MPI_COMM_WORLD);
    truth_ = testing::makeTruth(12, 20, true, 5);
    share_ = testing::shareOf(truth_, mpi::rank(), mpi::size());
    writeCheckpoint(dir_ / "run.h5", share_, MPI_COMM_WORLD);
  }
  void TearDown() override {
    MPI_Barrier(MPI_COMM_WORLD);
    if (mpi::rank() == 0) fs::remove_all(dir_);
  }

  /// Runs `make` on rank 0 (the others wait), so that every rank sees what it made.
  void onRankZero(const std::function<void()>& make) {
    if (mpi::rank() == 0) make();
    MPI_Barrier(MPI_COMM_WORLD);
  }

  /// The message of the CheckpointError that writing to `path` throws (on every rank), after
  /// checking that the folder holds the same entries as before (no temporary file).
  std::string refusal(const fs::path& path) {
    const auto before = entries(dir_);
    std::string message;
    try {
      writeCheckpoint(path, share_, MPI_COMM_WORLD);
      ADD_FAILURE() << "writing to " << path << " was not refused";
    } catch (const CheckpointError& e) {
      message = e.what();
    }
    MPI_Barrier(MPI_COMM_WORLD);
    EXPECT_EQ(entries(dir_), before);
    MPI_Barrier(MPI_COMM_WORLD);  // every rank has looked before rank 0 makes the next file
    return message;
  }

  /// The checkpoint at `path` holds this test's data.
  void expectCheckpoint(const fs::path& path) {
    const CheckpointSummary s = verifyCheckpoint(path, MPI_COMM_WORLD);
    EXPECT_EQ(s.particles, static_cast<std::int64_t>(truth_.free.size() + truth_.globals.size()));
  }

  fs::path dir_;
  testing::Truth truth_;
  sim::CheckpointData share_;
};

#define EXPECT_CONTAINS(text, part) \
  EXPECT_NE((text).find(part), std::string::npos) << "'" << (part) << "' not in: " << (text)

TEST_F(CheckpointTarget, FifoIsRefusedAndStaysAFifo) {
  const fs::path fifo = dir_ / "pipe.h5";
  onRankZero([&] { ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0); });
  const std::string m = refusal(fifo);
  EXPECT_CONTAINS(m, "checkpoint " + fifo.string() + ": is a FIFO (named pipe), not a file");
  EXPECT_TRUE(fs::is_fifo(fifo));
}

TEST_F(CheckpointTarget, DevNullIsRefusedAndLeftAlone) {
  struct stat before {};
  ASSERT_EQ(stat("/dev/null", &before), 0);
  ASSERT_TRUE(S_ISCHR(before.st_mode));
  EXPECT_CONTAINS(refusal("/dev/null"), "checkpoint /dev/null: is a device, not a file");
  // Through a link in the test's folder too.
  const fs::path link = dir_ / "null.h5";
  onRankZero([&] { fs::create_symlink("/dev/null", link); });
  EXPECT_CONTAINS(refusal(link), "checkpoint " + link.string() +
                                     ": is a symbolic link to /dev/null, which is a device");
  EXPECT_TRUE(fs::is_symlink(link));
  struct stat after {};
  ASSERT_EQ(stat("/dev/null", &after), 0);
  EXPECT_TRUE(S_ISCHR(after.st_mode));
  EXPECT_EQ(after.st_rdev, before.st_rdev);
  EXPECT_EQ(after.st_ino, before.st_ino);
}

TEST_F(CheckpointTarget, CharacterDeviceMadeHereIsRefused) {
  // A device node of /dev/null's numbers in the test's folder (needs CAP_MKNOD: root, and a
  // container that allows it; elsewhere /dev/null itself covers the case above).
  const fs::path device = dir_ / "device.h5";
  int made = 0;
  if (mpi::rank() == 0) made = mknod(device.c_str(), S_IFCHR | 0600, makedev(1, 3)) == 0;
  MPI_Bcast(&made, 1, MPI_INT, 0, MPI_COMM_WORLD);
  if (!made) GTEST_SKIP() << "mknod is not allowed here";
  EXPECT_CONTAINS(refusal(device), "checkpoint " + device.string() + ": is a device, not a file");
  EXPECT_TRUE(fs::is_character_file(device));
}

TEST_F(CheckpointTarget, UnrelatedFilesAreRefusedAndUnchanged) {
  const fs::path notes = dir_ / "notes.h5", other_hdf5 = dir_ / "other.h5";
  onRankZero([&] {
    std::ofstream(notes) << "field notes, not a checkpoint";
    // An HDF5 file of another program: an HDF5 file, but not polydem's.
    const hid_t f = H5Fcreate(other_hdf5.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
    ASSERT_GE(f, 0);
    H5Fclose(f);
  });
  const std::string notes_bytes = testing::readBytes(notes);
  const std::string hdf5_bytes = testing::readBytes(other_hdf5);
  const std::string m = refusal(notes);
  EXPECT_CONTAINS(m, "checkpoint " + notes.string() + ": exists and is not a polydem checkpoint (" +
                         std::to_string(notes_bytes.size()) + " bytes)");
  EXPECT_CONTAINS(m, "remove the file or choose another path");
  EXPECT_EQ(testing::readBytes(notes), notes_bytes);
  EXPECT_CONTAINS(refusal(other_hdf5), "is not a polydem checkpoint");
  EXPECT_EQ(testing::readBytes(other_hdf5), hdf5_bytes);
}

TEST_F(CheckpointTarget, DirectoriesAndDanglingLinksAreRefused) {
  const fs::path directory = dir_ / "folder.h5", dangling = dir_ / "dangling.h5";
  const fs::path to_directory = dir_ / "to_folder.h5";
  onRankZero([&] {
    fs::create_directory(directory);
    fs::create_symlink("absent.h5", dangling);
    fs::create_symlink("folder.h5", to_directory);
  });
  EXPECT_CONTAINS(refusal(directory), "checkpoint " + directory.string() + ": is a directory");
  EXPECT_CONTAINS(refusal(dangling), "checkpoint " + dangling.string() +
                                         ": is a symbolic link to absent.h5, which does not exist");
  EXPECT_CONTAINS(refusal(to_directory), "which is a directory");
  EXPECT_TRUE(fs::is_symlink(dangling));
  EXPECT_TRUE(fs::is_symlink(to_directory));
}

TEST_F(CheckpointTarget, EmptyFileAndCheckpointAreReplaced) {
  const fs::path empty = dir_ / "empty.h5";  // as tempfile.mkstemp() leaves it
  onRankZero([&] { std::ofstream out(empty); });
  writeCheckpoint(empty, share_, MPI_COMM_WORLD);
  expectCheckpoint(empty);
  // run.h5 holds a checkpoint (SetUp): replaced by the next one.
  const auto later = testing::makeTruth(30, 10, true, 6);
  writeCheckpoint(dir_ / "run.h5", testing::shareOf(later, mpi::rank(), mpi::size()),
                  MPI_COMM_WORLD);
  const CheckpointSummary s = verifyCheckpoint(dir_ / "run.h5", MPI_COMM_WORLD);
  EXPECT_EQ(s.particles, static_cast<std::int64_t>(later.free.size() + later.globals.size()));
}

TEST_F(CheckpointTarget, LinkToACheckpointReplacesTheFileItNames) {
  const fs::path link = dir_ / "latest.h5", target = dir_ / "run.h5";
  onRankZero([&] { fs::create_symlink("run.h5", link); });
  const auto later = testing::makeTruth(30, 10, true, 7);
  writeCheckpoint(link, testing::shareOf(later, mpi::rank(), mpi::size()), MPI_COMM_WORLD);
  MPI_Barrier(MPI_COMM_WORLD);
  EXPECT_TRUE(fs::is_symlink(link));
  EXPECT_EQ(fs::read_symlink(link), "run.h5");
  const CheckpointSummary s = verifyCheckpoint(target, MPI_COMM_WORLD);
  EXPECT_EQ(s.particles, static_cast<std::int64_t>(later.free.size() + later.globals.size()));
  EXPECT_EQ(entries(dir_), (std::vector<std::string>{"latest.h5", "run.h5"}));
}

}  // namespace
}  // namespace polydem::checkpoint
