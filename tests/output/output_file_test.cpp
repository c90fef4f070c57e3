#include "polydem/output/output_file.h"

#include <gtest/gtest.h>
#include <mpi.h>

#include <filesystem>
#include <fstream>

#include "output/output_test_util.h"
#include "output/vtk_test_reader.h"
#include "polydem/core/error.h"
#include "polydem/core/mpi_env.h"

namespace polydem::output {
namespace {

namespace fs = std::filesystem;

TEST(AtomicFile, AppearsOnlyWhenCommitted) {
  const test::ScratchDir scratch("atomic", MPI_COMM_SELF);
  const std::string& dir = scratch.path();
  const std::string path = dir + "/a.txt";
  {
    AtomicFile file(path);
    file.write("hello ");
    file.write("world\n");
    EXPECT_FALSE(fs::exists(path));
    EXPECT_TRUE(fs::exists(path + ".tmp"));
    file.commit();
    EXPECT_THROW(file.write("more"), Error);
  }
  EXPECT_EQ(test::readFile(path), "hello world\n");
  EXPECT_FALSE(fs::exists(path + ".tmp"));
  {
    AtomicFile abandoned(path);  // an exception on the way: never committed
    abandoned.write("half");
  }
  EXPECT_EQ(test::readFile(path), "hello world\n");
  EXPECT_FALSE(fs::exists(path + ".tmp"));
}

TEST(AtomicFile, FullDiskThrowsNamingThePathAndKeepsTheOldFile) {
  if (!fs::exists("/dev/full")) GTEST_SKIP() << "no /dev/full";
  const test::ScratchDir scratch("full", MPI_COMM_SELF);
  const std::string& dir = scratch.path();
  const std::string path = dir + "/summary.json";
  writeFileAtomic(path, "old\n");
  // The temporary name leads to /dev/full: every write fails with ENOSPC.
  fs::create_symlink("/dev/full", path + ".tmp");
  try {
    writeFileAtomic(path, "new\n");
    FAIL() << "no error";
  } catch (const Error& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find(path), std::string::npos) << message;
    EXPECT_NE(message.find("No space left"), std::string::npos) << message;
  }
  EXPECT_EQ(test::readFile(path), "old\n");
  EXPECT_FALSE(fs::exists(fs::symlink_status(path + ".tmp")));
}

TEST(AtomicFile, MissingDirectoryThrowsNamingThePath) {
  const std::string path = "/nonexistent-polydem-dir/x/summary.json";
  try {
    writeFileAtomic(path, "x");
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
  }
}

TEST(CollectiveFailure, EveryRankThrowsTheLowestFailingRanksMessage) {
  const int rank = mpi::rank(), size = mpi::size();
  EXPECT_NO_THROW(throwIfAnyRankFailed("", MPI_COMM_WORLD));
  const int failing = size - 1;  // the last rank fails (rank 0 when alone)
  try {
    throwIfAnyRankFailed(rank == failing ? "cannot write /x/y.vtp: disk full" : "", MPI_COMM_WORLD);
    FAIL() << "no error on rank " << rank;
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()).rfind("cannot write /x/y.vtp: disk full", 0), 0u) << e.what();
  }
}

}  // namespace
}  // namespace polydem::output
