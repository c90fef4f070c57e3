// writeCheckpoint: validation, the temporary file, the datasets, the atomic rename.
#include <fcntl.h>
#include <sys/resource.h>
#include <sys/statvfs.h>
#include <unistd.h>

#include <cstring>
#include <system_error>

#include "polydem/checkpoint/checkpoint.h"
#include "polydem/checkpoint/checkpoint_layout.h"
#include "polydem/checkpoint/checkpoint_read_all.h"
#include "polydem/checkpoint/checkpoint_writer.h"
#include "polydem/core/error.h"
#include "polydem/core/mpi_env.h"
#include "polydem/core/strings.h"
#include "polydem/core/test_pause.h"
#include "polydem/hdf5/hdf5_file.h"

namespace polydem::checkpoint {

namespace {

namespace fs = std::filesystem;
using particles::Particle;

/// Problems with the caller's data on this rank (checked before any file is touched).
std::optional<std::string> invalidData(const sim::CheckpointData& data, int rank) {
  const auto shapes = static_cast<std::int32_t>(data.shapes.size());
  const auto materials = static_cast<std::int32_t>(data.materials.size());
  for (const Particle& p : data.particles) {
    if (p.isGhost()) return cat("particle uid ", p.uid, " is a ghost copy; pass owned ones only");
    if (p.shape < 0 || p.shape >= shapes) {
      return cat("particle uid ", p.uid, " has shape ", p.shape, " but the table has ", shapes);
    }
    if (p.material < 0 || p.material >= materials) {
      return cat("particle uid ", p.uid, " has material ", p.material, " but the table has ",
                 materials);
    }
  }
  if (data.pair_keys.size() != data.pair_histories.size()) {
    return cat(data.pair_keys.size(), " pair keys but ", data.pair_histories.size(), " histories");
  }
  for (const auto& k : data.pair_keys) {
    if (!(k.lo < k.hi)) return cat("pair (", k.lo, ", ", k.hi, ") is not ordered lo < hi");
  }
  if (data.sub_keys.size() != data.sub_histories.size()) {
    return cat(data.sub_keys.size(), " sub-contact keys but ", data.sub_histories.size(),
               " histories");
  }
  for (const auto& k : data.sub_keys) {
    if (!(k.pair.lo < k.pair.hi)) {
      return cat("sub-contact of pair (", k.pair.lo, ", ", k.pair.hi, ") is not ordered lo < hi");
    }
  }
  if (rank != 0) return std::nullopt;  // the replicated part is written from rank 0's copy
  const auto& d = data.domain;
  const std::int64_t blocks = std::int64_t{d.blocks[0]} * d.blocks[1] * d.blocks[2];
  if (d.blocks[0] < 1 || d.blocks[1] < 1 || d.blocks[2] < 1 ||
      static_cast<std::int64_t>(d.rank_map.size()) != blocks) {
    return cat("the rank map has ", d.rank_map.size(), " entries for ", blocks, " blocks");
  }
  for (const auto& s : data.shapes) {
    for (const auto& face : s.faces) {
      for (int v : face) {
        if (v < 0 || v >= static_cast<int>(s.vertices.size())) {
          return cat("shape '", s.name, "' has a face with vertex ", v, " of ", s.vertices.size());
        }
      }
    }
  }
  for (const auto& in : data.interactions) {
    if (in.a < 0 || in.a >= materials || in.b < 0 || in.b >= materials) {
      return cat("interaction (", in.a, ", ", in.b, ") names a material out of range");
    }
  }
  const double exact = ExactSum::fromDigits(data.time_digits).value();
  if (std::memcmp(&exact, &data.time, sizeof exact) != 0) {
    return cat("time ", data.time, " is not the rounded exact time ", exact,
               " (pass TimeLoop::exactTime().digits())");
  }
  return stepTimeProblem(data);
}

/// Bytes the file will take, about: every dataset's payload (the replicated tables are small) and
/// room for HDF5's metadata. Collective.
std::uint64_t estimatedBytes(const sim::CheckpointData& data, MPI_Comm comm) {
  const auto& view = data.history_view;
  const std::uint64_t pairs = view.table ? view.pairs.size() : data.pair_keys.size();
  const std::uint64_t subs = view.table ? view.subCount() : data.sub_keys.size();
  std::uint64_t mine = data.particles.size() * layout::kParticleRowBytes +
                       pairs * layout::kPairRowBytes + subs * layout::kSubRowBytes;
  if (mpi::rank(comm) == 0) {
    mine += data.scene_toml.size() + data.run_state.size();
    for (const auto& s : data.shapes) mine += 48 * s.vertices.size() + 64 * s.faces.size() + 256;
  }
  std::uint64_t total = 0;
  MPI_Allreduce(&mine, &total, 1, MPI_UINT64_T, MPI_SUM, comm);
  return total + (std::uint64_t{1} << 20);
}

/// A write that cannot fit is refused before it starts, from an estimate; the file layer takes
/// the exact space as the file grows (disk_space.h). A file size limit is checked on every rank:
/// a write beyond it kills the process (SIGXFSZ).
std::optional<std::string> noRoomFor(std::uint64_t bytes, const fs::path& path, int rank) {
  rlimit limit{};
  if (getrlimit(RLIMIT_FSIZE, &limit) == 0 && limit.rlim_cur != RLIM_INFINITY &&
      bytes > limit.rlim_cur) {
    return cat("needs about ", bytes, " bytes, above the file size limit of ", limit.rlim_cur,
               " bytes (ulimit -f) of rank ", rank);
  }
  struct statvfs fs_info {};
  const fs::path dir = path.parent_path().empty() ? fs::path(".") : path.parent_path();
  if (rank == 0 && statvfs(dir.c_str(), &fs_info) == 0) {
    const std::uint64_t available = std::uint64_t{fs_info.f_bavail} * fs_info.f_frsize;
    if (bytes > available) {
      return cat("no space left on device: it needs about ", bytes, " bytes but only ", available,
                 " are free in ", dir.string());
    }
  }
  return std::nullopt;
}

/// Makes a rename durable: fsync of the directory that holds the entry.
void syncDirectory(const fs::path& dir) {
  const int fd = ::open(dir.empty() ? "." : dir.c_str(), O_RDONLY | O_DIRECTORY);
  if (fd < 0) return;
  ::fsync(fd);
  ::close(fd);
}

}  // namespace

void writeCheckpoint(const fs::path& requested, const sim::CheckpointData& data, MPI_Comm comm,
                     const hdf5::CheckpointIoOptions& options) {
  const fs::path path =
      checkpointTarget(requested, comm);  // nothing but a new file or a checkpoint
  const hdf5::ErrorSilencer silence;
  const int rank = mpi::rank(comm);
  std::optional<std::string> problem = invalidData(data, rank);
  if (problem) problem = "checkpoint " + path.string() + ": " + *problem;
  hdf5::agree(problem, comm);
  problem = noRoomFor(estimatedBytes(data, comm), path, rank);
  if (problem) problem = "checkpoint " + path.string() + ": " + *problem;
  hdf5::agree(problem, comm);
  std::int64_t pid = ::getpid();
  MPI_Bcast(&pid, 1, MPI_INT64_T, 0, comm);
  const fs::path temporary = path.string() + ".tmp." + std::to_string(pid);

  std::optional<std::string> failure;
  try {
    hdf5::File file = hdf5::File::create(temporary, comm, options, path.string());
    if (rank == 0) testPause("checkpoint-write");  // test hook (core/test_pause.h)
    writeContents(file, data);
    file.close();  // H5Fflush (MPI_File_sync) and H5Fclose
  } catch (const CheckpointError& e) {
    failure = e.what();  // agreed: every rank is here, and the file is closed on every rank
  }
  MPI_Barrier(comm);
  if (rank == 0) {
    std::error_code ec;
    if (!failure) testPause("before-rename");
    if (!failure) {
      fs::rename(temporary, path, ec);  // atomic on POSIX: readers see the old or the new file
      if (ec) {
        failure = "checkpoint " + path.string() + ": cannot rename " + temporary.string() +
                  " to it: " + ec.message();
      } else {
        syncDirectory(path.parent_path());
      }
    }
    if (failure) fs::remove(temporary, ec);
  }
  hdf5::agree(rank == 0 ? failure : std::nullopt, comm);
}

}  // namespace polydem::checkpoint
