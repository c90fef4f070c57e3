// Edited and mixed checkpoints: every change made to a file after polydem wrote
// it (an attribute of /run, a dataset copied in from another checkpoint of the same run with its
// own valid checksum, a dataset rewritten together with its checksum, anything added or deleted)
// is refused by the whole-file digest on every rank, by readCheckpoint and verifyCheckpoint
// alike. Resealed (the digest recomputed on purpose), the run's values are still checked: a
// negative step, a step that does not match the time, an unknown dataset.
#include <gtest/gtest.h>
#include <hdf5.h>
#include <mpi.h>

#include <functional>

#include "checkpoint_edit_util.h"
#include "checkpoint_test_data.h"
#include "polydem/checkpoint/checkpoint.h"
#include "polydem/core/error.h"
#include "polydem/core/mpi_env.h"
#include "polydem/core/strings.h"
#include "polydem/hdf5/checksum.h"

namespace polydem::checkpoint {
namespace {

namespace fs = std::filesystem;

using testing::editFile;
using testing::readBytes;
using testing::reseal;
using testing::setAttribute;

/// Copies dataset `name` (data and attributes) from `from` over the one in `to` (serial HDF5).
void copyDataset(hid_t from, hid_t to, const char* name) {
  H5Ldelete(to, name, H5P_DEFAULT);
  ASSERT_GE(H5Ocopy(from, name, to, name, H5P_DEFAULT, H5P_DEFAULT), 0) << name;
}

class CheckpointEdits : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = testing::scratchDirectory("checkpoint_edits", MPI_COMM_WORLD);
    good_ = dir_ / "good.h5";
    later_ = dir_ / "later.h5";
    const testing::Truth truth = testing::makeTruth();
    writeCheckpoint(good_, testing::shareOf(truth, mpi::rank(), mpi::size()), MPI_COMM_WORLD);
    // The same run further on: every free particle moved, the pair histories changed.
    testing::Truth later = truth;
    for (auto& p : later.free) {
      p.position += Vec3(0.25, 0.0, -0.5);
      p.velocity *= 0.5;
    }
    for (auto& h : later.histories) h.shear_force *= 0.5;
    writeCheckpoint(later_, testing::shareOf(later, mpi::rank(), mpi::size()), MPI_COMM_WORLD);
  }
  void TearDown() override {
    MPI_Barrier(MPI_COMM_WORLD);
    if (mpi::rank() == 0) fs::remove_all(dir_);
  }

  /// A copy of the good file edited (serial HDF5, rank 0) by `edit`, then resealed if asked.
  fs::path edited(const std::string& name, const std::function<void(hid_t)>& edit,
                  bool resealed = false) {
    const fs::path path = dir_ / (name + (resealed ? "_resealed.h5" : ".h5"));
    if (mpi::rank() == 0) {
      fs::copy_file(good_, path, fs::copy_options::overwrite_existing);
      editFile(path, edit);
      if (resealed) reseal(path);
    }
    MPI_Barrier(MPI_COMM_WORLD);
    return path;
  }

  /// readCheckpoint and verifyCheckpoint refuse `path` on every rank with a message naming the
  /// file and containing `part`; the file is left as it was.
  void expectRefused(const fs::path& path, const std::string& part) {
    const std::string before = readBytes(path);
    for (const bool verify : {false, true}) {
      std::string message;
      try {
        if (verify) {
          verifyCheckpoint(path, MPI_COMM_WORLD);
        } else {
          readCheckpoint(path, MPI_COMM_WORLD);
        }
        ADD_FAILURE() << path << " was accepted";
      } catch (const CheckpointError& e) {
        message = e.what();
      }
      EXPECT_NE(message.find(path.string()), std::string::npos) << message;
      EXPECT_NE(message.find(part), std::string::npos) << "expected '" << part << "': " << message;
    }
    EXPECT_EQ(readBytes(path), before);
  }

  void expectEditRefused(const std::string& name, const std::function<void(hid_t)>& edit) {
    SCOPED_TRACE(name);
    expectRefused(edited(name, edit), "the file was changed after it was written");
  }

  fs::path dir_, good_, later_;
};

TEST_F(CheckpointEdits, UntouchedFilesAndCopiesRead) {
  const auto copy = edited("copy", [](hid_t) {});
  for (const auto& path : {good_, later_, copy}) {
    const CheckpointSummary s = verifyCheckpoint(path, MPI_COMM_WORLD);
    EXPECT_NE(s.digest, 0u);
  }
  EXPECT_NE(verifyCheckpoint(good_, MPI_COMM_WORLD).digest,
            verifyCheckpoint(later_, MPI_COMM_WORLD).digest);
}

TEST_F(CheckpointEdits, RunAttributes) {
  const hid_t i64 = H5T_STD_I64LE, n64 = H5T_NATIVE_INT64;
  for (const std::int64_t step : {-5, 2001, 4322}) {
    expectEditRefused(cat("step", step), [&](hid_t f) {
      setAttribute<std::int64_t>(f, "/run", "step", i64, n64, {step});
    });
  }
  expectEditRefused("equilibrium_steps", [&](hid_t f) {
    setAttribute<std::int64_t>(f, "/run", "equilibrium_steps", i64, n64, {0});
  });
  expectEditRefused("stage", [](hid_t f) {
    setAttribute<std::int32_t>(f, "/run", "stage", H5T_STD_I32LE, H5T_NATIVE_INT32, {1});
  });
  expectEditRefused("reached", [](hid_t f) {
    setAttribute<std::uint8_t>(f, "/run", "equilibrium_reached", H5T_STD_U8LE, H5T_NATIVE_UINT8,
                               {0});
  });
  expectEditRefused("dt", [](hid_t f) {
    setAttribute<double>(f, "/run", "dt", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, {1.2e-4});
  });
  expectEditRefused("writer_ranks", [](hid_t f) {
    setAttribute<std::int32_t>(f, "/", "writer_ranks", H5T_STD_I32LE, H5T_NATIVE_INT32, {7});
  });
  expectEditRefused("replicated", [](hid_t f) {
    setAttribute<std::uint64_t>(f, "/particles", "replicated_count", H5T_STD_U64LE,
                                H5T_NATIVE_UINT64, {0});
  });
  expectEditRefused("domain_ranks", [](hid_t f) {
    setAttribute<std::int32_t>(f, "/domain", "ranks", H5T_STD_I32LE, H5T_NATIVE_INT32, {5});
  });
  expectEditRefused("extra_attribute", [](hid_t f) {
    setAttribute<double>(f, "/contacts", "note", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, {1.0});
  });
}

TEST_F(CheckpointEdits, DatasetsFromAnotherCheckpointOfTheSameRun) {
  // Each copied dataset carries its own valid checksum: only the digest tells the mix apart.
  const fs::path later = later_;
  auto from_later = [later](const std::function<void(hid_t, hid_t)>& edit) {
    return [later, edit](hid_t f) {
      const hid_t source = H5Fopen(later.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
      edit(source, f);
      H5Fclose(source);
    };
  };
  for (const char* name : {"/particles/position", "/particles/velocity", "/contacts/shear_force"}) {
    expectEditRefused(cat("mixed", std::string(name).substr(1, 4), name[11]),
                      from_later([name](hid_t source, hid_t f) { copyDataset(source, f, name); }));
  }
  // The whole /particles group, with its attributes.
  expectEditRefused(
      "mixed_group", from_later([](hid_t source, hid_t f) {
        H5Ldelete(f, "/particles", H5P_DEFAULT);
        ASSERT_GE(H5Ocopy(source, "/particles", f, "/particles", H5P_DEFAULT, H5P_DEFAULT), 0);
      }));
}

TEST_F(CheckpointEdits, DataRewrittenWithAMatchingChecksum) {
  // A forger who knows polydem-sum64 rewrites the data and the dataset's checksum attribute;
  // without the digest, the reader would accept it.
  expectEditRefused("rewritten", [](hid_t f) {
    const hid_t d = H5Dopen2(f, "/domain/lo", H5P_DEFAULT);
    const double lo[3] = {-1000.0, -1000.0, -1000.0};
    H5Dwrite(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, lo);
    H5Dclose(d);
    const std::uint64_t sum = hdf5::checksumFinish(hdf5::checksumPartial(lo, 3, 8, 0), 3);
    setAttribute<std::uint64_t>(f, "/domain/lo", "checksum", H5T_STD_U64LE, H5T_NATIVE_UINT64,
                                {sum});
  });
}

TEST_F(CheckpointEdits, ThingsAddedOrRemoved) {
  auto add_dataset = [](hid_t f) {
    const hsize_t n = 2;
    const hid_t space = H5Screate_simple(1, &n, nullptr);
    const hid_t d = H5Dcreate2(f, "/particles/extra", H5T_IEEE_F64LE, space, H5P_DEFAULT,
                               H5P_DEFAULT, H5P_DEFAULT);
    const double v[2] = {1, 2};
    H5Dwrite(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v);
    H5Dclose(d);
    H5Sclose(space);
  };
  expectEditRefused("added_dataset", add_dataset);
  expectEditRefused("description", [](hid_t f) {
    H5Adelete_by_name(f, "/particles/velocity", "description", H5P_DEFAULT);
  });
  expectEditRefused("soft_link", [](hid_t f) {
    H5Lcreate_soft("/particles/position", f, "/contacts/position", H5P_DEFAULT, H5P_DEFAULT);
  });
  expectEditRefused("group", [](hid_t f) {
    H5Gclose(H5Gcreate2(f, "/notes", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT));
  });
  expectRefused(
      edited("no_digest",
             [](hid_t f) { H5Adelete_by_name(f, "/", hdf5::kDigestAttribute, H5P_DEFAULT); }),
      "attribute digest of / is missing");
  // Resealed, a dataset the reader does not read is still refused rather than ignored.
  expectRefused(edited("added_dataset", add_dataset, true),
                cat("dataset /particles/extra is not part of a version ", kCheckpointFormatVersion,
                    " checkpoint"));
}

TEST_F(CheckpointEdits, ResealedStepsAreStillChecked) {
  const hid_t i64 = H5T_STD_I64LE, n64 = H5T_NATIVE_INT64;
  auto step = [&](std::int64_t value) {
    return [=](hid_t f) { setAttribute<std::int64_t>(f, "/run", "step", i64, n64, {value}); };
  };
  expectRefused(edited("step-5", step(-5), true), "/run: step -5 or equilibrium_steps");
  // The equilibrium stage's step is its step count; a consistent pair that is not step x dt:
  expectRefused(edited(
                    "step2001",
                    [&](hid_t f) {
                      step(2001)(f);
                      setAttribute<std::int64_t>(f, "/run", "equilibrium_steps", i64, n64, {2001});
                    },
                    true),
                "is not step 2001 x dt");
  expectRefused(edited("step4322", step(4322), true), "equilibrium_steps is 4321");
}

}  // namespace
}  // namespace polydem::checkpoint
