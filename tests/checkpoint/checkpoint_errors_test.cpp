// Damaged and mismatched checkpoints: each problem is a CheckpointError on every rank that names
// the file and the dataset, and reading never changes the file. Edits of the file's structure are
// refused by the whole-file digest (checkpoint_edit_test.cpp); here they are resealed (the digest
// recomputed) to reach the checks behind it.
#include <gtest/gtest.h>
#include <hdf5.h>
#include <mpi.h>
#include <sys/stat.h>

#include <fstream>
#include <functional>
#include <sstream>

#include "checkpoint_edit_util.h"
#include "checkpoint_test_data.h"
#include "polydem/checkpoint/checkpoint.h"
#include "polydem/core/error.h"
#include "polydem/core/mpi_env.h"
#include "polydem/core/strings.h"

namespace polydem::checkpoint {
namespace {

namespace fs = std::filesystem;

using testing::editFile;
using testing::readBytes;
using testing::reseal;
using testing::writeBytes;

/// Byte offset of a contiguous dataset's data in the file (serial HDF5).
std::uint64_t dataOffset(const fs::path& path, const char* dataset) {
  const hid_t f = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  const hid_t d = H5Dopen2(f, dataset, H5P_DEFAULT);
  const haddr_t offset = H5Dget_offset(d);
  H5Dclose(d);
  H5Fclose(f);
  return offset;
}

class CheckpointErrors : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = testing::scratchDirectory("checkpoint_errors", MPI_COMM_WORLD);
    good_ = dir_ / "good.h5";
    truth_ = testing::makeTruth();
    writeCheckpoint(good_, testing::shareOf(truth_, mpi::rank(), mpi::size()), MPI_COMM_WORLD);
  }
  void TearDown() override {
    MPI_Barrier(MPI_COMM_WORLD);
    if (mpi::rank() == 0) fs::remove_all(dir_);
  }

  /// A copy of the good file, changed by `damage` on rank 0.
  fs::path damaged(const std::string& name, const std::function<void(const fs::path&)>& damage) {
    const fs::path path = dir_ / name;
    if (mpi::rank() == 0) {
      fs::copy_file(good_, path, fs::copy_options::overwrite_existing);
      damage(path);
    }
    MPI_Barrier(MPI_COMM_WORLD);
    return path;
  }

  /// Reading `path` fails on every rank with a message naming the file and each of `parts`, and
  /// leaves the file as it was.
  void expectRejected(const fs::path& path, const std::vector<std::string>& parts) {
    const std::string before = readBytes(path);
    std::string message;
    try {
      readCheckpoint(path, MPI_COMM_WORLD);
      ADD_FAILURE() << "reading " << path << " did not fail";
    } catch (const CheckpointError& e) {
      message = e.what();
    }
    EXPECT_NE(message.find(path.string()), std::string::npos) << message;
    for (const auto& part : parts) EXPECT_NE(message.find(part), std::string::npos) << message;
    EXPECT_THROW(verifyCheckpoint(path, MPI_COMM_WORLD), CheckpointError);
    EXPECT_EQ(readBytes(path), before) << "the failed read changed " << path;
  }

  void flipDataByte(const fs::path& path, const char* dataset, std::uint64_t at = 5) {
    std::string bytes = readBytes(path);
    const std::uint64_t offset = dataOffset(path, dataset) + at;
    ASSERT_LT(offset, bytes.size());
    bytes[offset] = static_cast<char>(bytes[offset] ^ 0x10);
    writeBytes(path, bytes);
  }

  fs::path dir_, good_;
  testing::Truth truth_;
};

TEST_F(CheckpointErrors, TheGoodFileReads) {
  EXPECT_NO_THROW(readCheckpoint(good_, MPI_COMM_WORLD));
}

TEST_F(CheckpointErrors, TruncatedFile) {
  const auto path = damaged("truncated.h5", [](const fs::path& p) {
    const std::string bytes = readBytes(p);
    writeBytes(p, bytes.substr(0, bytes.size() / 2));
  });
  expectRejected(path, {"truncated"});
}

TEST_F(CheckpointErrors, CorruptedBytesNameTheDataset) {
  for (const char* dataset :
       {"/particles/position", "/particles/uid", "/contacts/shear_force", "/contacts/touching",
        "/shapes/vertices", "/materials/kn", "/scene/toml", "/run/state", "/domain/rank_map"}) {
    std::string name = std::string("flip") + dataset + ".h5";
    std::replace(name.begin(), name.end(), '/', '_');
    const auto path = damaged(name, [&](const fs::path& p) { flipDataByte(p, dataset, 1); });
    expectRejected(path, {std::string("dataset ") + dataset + " is corrupted"});
  }
}

TEST_F(CheckpointErrors, AnotherFormatVersion) {
  // Versions before the oldest readable one and after this polydem's are refused (older ones that
  // are readable are tested in sim_restart and checkpoint_summary_test.py).
  for (const std::int32_t version : {0, kCheckpointFormatVersion + 1}) {
    const auto path = damaged(cat("version", version, ".h5"), [&](const fs::path& p) {
      editFile(p, [&](hid_t f) {
        const hid_t a = H5Aopen_by_name(f, "/", "format_version", H5P_DEFAULT, H5P_DEFAULT);
        H5Awrite(a, H5T_NATIVE_INT32, &version);
        H5Aclose(a);
      });
    });
    expectRejected(path, {cat("format version ", version, " (written by polydem "),
                          cat("reads versions 1 to ", kCheckpointFormatVersion)});
  }
}

TEST_F(CheckpointErrors, MissingDataset) {
  const auto path = damaged("missing.h5", [](const fs::path& p) {
    editFile(p, [](hid_t f) { H5Ldelete(f, "/contacts/normal", H5P_DEFAULT); });
    reseal(p);
  });
  expectRejected(path, {"dataset /contacts/normal is missing"});
}

TEST_F(CheckpointErrors, MissingGroup) {
  const auto path = damaged("nogroup.h5", [](const fs::path& p) {
    editFile(p, [](hid_t f) { H5Ldelete(f, "/materials", H5P_DEFAULT); });
    reseal(p);
  });
  expectRejected(path, {"/materials/name is missing"});
}

TEST_F(CheckpointErrors, InconsistentSizes) {
  const std::uint64_t n = truth_.free.size() + truth_.globals.size();
  const auto path = damaged("sizes.h5", [&](const fs::path& p) {
    editFile(p, [&](hid_t f) {
      H5Ldelete(f, "/particles/velocity", H5P_DEFAULT);
      const hsize_t dims[2] = {n - 1, 3};
      const hid_t space = H5Screate_simple(2, dims, nullptr);
      const hid_t d = H5Dcreate2(f, "/particles/velocity", H5T_IEEE_F64LE, space, H5P_DEFAULT,
                                 H5P_DEFAULT, H5P_DEFAULT);
      const std::vector<double> zeros(3 * (n - 1), 0.0);
      H5Dwrite(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, zeros.data());
      H5Dclose(d);
      H5Sclose(space);
    });
    reseal(p);
  });
  expectRejected(path, {"dataset /particles/velocity has shape " + std::to_string(n - 1) +
                            " x 3, expected " + std::to_string(n) + " x 3",
                        "inconsistent sizes"});
}

TEST_F(CheckpointErrors, WrongType) {
  const std::uint64_t n = truth_.free.size() + truth_.globals.size();
  const auto path = damaged("type.h5", [&](const fs::path& p) {
    editFile(p, [&](hid_t f) {
      H5Ldelete(f, "/particles/shape", H5P_DEFAULT);
      const hsize_t dim = n;
      const hid_t space = H5Screate_simple(1, &dim, nullptr);
      const hid_t d = H5Dcreate2(f, "/particles/shape", H5T_IEEE_F64LE, space, H5P_DEFAULT,
                                 H5P_DEFAULT, H5P_DEFAULT);
      H5Dclose(d);
      H5Sclose(space);
    });
    reseal(p);
  });
  expectRejected(path, {"dataset /particles/shape holds 64-bit float values"});
}

TEST_F(CheckpointErrors, TimeThatIsNotTheExactTime) {
  const auto path = damaged("time.h5", [](const fs::path& p) {
    editFile(p, [](hid_t f) {
      // Replaced rather than rewritten: H5Awrite fails on the densely stored /run attributes.
      H5Adelete_by_name(f, "/run", "time", H5P_DEFAULT);
      const hid_t space = H5Screate(H5S_SCALAR);
      const hid_t a = H5Acreate_by_name(f, "/run", "time", H5T_IEEE_F64LE, space, H5P_DEFAULT,
                                        H5P_DEFAULT, H5P_DEFAULT);
      const double t = 0.5;
      H5Awrite(a, H5T_NATIVE_DOUBLE, &t);
      H5Aclose(a);
      H5Sclose(space);
    });
    reseal(p);
  });
  expectRejected(path, {"/run: time 0.5 is not the rounded time_digits"});
}

TEST_F(CheckpointErrors, DamagedMetadata) {
  // The /run object header holds the attribute names; its checksum (HDF5 object header v2) fails.
  const auto path = damaged("header.h5", [](const fs::path& p) {
    std::string bytes = readBytes(p);
    const auto at = bytes.find("equilibrium_steps");
    ASSERT_NE(at, std::string::npos);
    bytes[at + 3] = 'X';
    writeBytes(p, bytes);
  });
  expectRejected(path, {});
}

TEST_F(CheckpointErrors, NotACheckpoint) {
  const auto text = damaged("text.h5", [](const fs::path& p) { writeBytes(p, "hello\n"); });
  expectRejected(text, {"not a readable HDF5 file"});
  const auto other = damaged("other.h5", [](const fs::path& p) {
    const hid_t f = H5Fcreate(p.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
    H5Fclose(f);
  });
  expectRejected(other, {"attribute format of / is missing"});
  std::string message;
  try {
    readCheckpoint(dir_ / "absent.h5", MPI_COMM_WORLD);
  } catch (const CheckpointError& e) {
    message = e.what();
  }
  EXPECT_NE(message.find("absent.h5: no such file"), std::string::npos) << message;
  // A directory and a FIFO are named as such (a FIFO must not block the reader).
  const fs::path directory = dir_ / "directory.h5", fifo = dir_ / "fifo.h5";
  if (mpi::rank() == 0) {
    fs::create_directory(directory);
    ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
  }
  MPI_Barrier(MPI_COMM_WORLD);
  expectRejected(directory, {"directory.h5: is a directory"});
  expectRejected(fifo, {"fifo.h5: is a FIFO (named pipe), not a file"});
}

}  // namespace
}  // namespace polydem::checkpoint
