// Checkpoints: one self-describing parallel HDF5 file holds everything a run needs to continue
// bit for bit, on the same or on another number of ranks. The layout (every dataset, attribute,
// type, unit, and the checksum) is documented in docs/checkpoint.md; any HDF5 tool can read it.
//
// Writing is collective: every rank writes its own particles and pair histories as a hyperslab of
// each dataset with collective MPI-IO transfers, into `path.tmp.<pid>` in the same directory; the
// file is flushed (MPI_File_sync) and closed, and only then does rank 0 rename it to `path`. A
// write that fails on any rank fails on every rank with CheckpointError, removes the temporary file
// and leaves an older file at `path` untouched.
//
// Reading is collective: every rank reads the replicated parts and a contiguous share of the
// particles and pair histories (rank r of P gets slice r); the caller then moves particles to their
// owners (ParticleExchange::migrate) and pair histories to the owners of their particles
// (comm/history_routing.h). The whole-file digest (hdf5/file_digest.h) is verified first, then
// every dataset's checksum, shape and type, and that the file holds no dataset the reader does not
// read; every problem is a CheckpointError naming the file and the dataset.
#pragma once

#include <mpi.h>

#include <array>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "polydem/core/exact_sum.h"
#include "polydem/core/types.h"
#include "polydem/hdf5/file_options.h"
#include "polydem/particles/contact_history.h"
#include "polydem/particles/material.h"
#include "polydem/particles/particle.h"
#include "polydem/particles/particle_storage.h"
#include "polydem/setup/setup.h"
#include "polydem/sim/history_chunks.h"
#include "polydem/sim/saved_state.h"

namespace polydem::checkpoint {

/// Version of the file layout. Version 2 added sub-contacts (/subcontacts) and the joint
/// stiffnesses (jkn/jks columns), version 3 the whole-file digest (hdf5/file_digest.h),
/// version 4 the faces' joint planes (/shapes/face_plane), version 5 the joint laws' history per
/// sub-contact (/subcontacts/law_state), version 6 the bolts' state (/bolts).
/// readCheckpoint() reads versions 1 to 6 and refuses others: a version 1 file continues with the
/// single-point contact model it was written with, files before version 3 are read on their
/// per-dataset checksums alone, with a warning, and files before version 4 continue without
/// joints: every contact takes its material pair's properties; files before version 5 continue
/// with every sub-contact's law history 0 (intact, not yet sheared); files before version 6 hold no
/// bolts (docs/checkpoint.md, 'Older files').
inline constexpr int kCheckpointFormatVersion = 6;
inline constexpr int kOldestReadableCheckpointVersion = 1;
inline constexpr int kFirstDigestCheckpointVersion = 3;

/// Writes `data` to `path` (collective; see the top of this file). Throws CheckpointError on every
/// rank if any rank fails (invalid data, I/O error, rename); `path` is then left as it was.
/// `path` must be new, an empty file or a polydem checkpoint (checkpointTarget).
void writeCheckpoint(const std::filesystem::path& path, const sim::CheckpointData& data,
                     MPI_Comm comm, const hdf5::CheckpointIoOptions& options = {});

/// The file a checkpoint for `path` is written to (collective): `path` itself if nothing has that
/// name, or it is an empty regular file or a polydem checkpoint (replaced); for a symbolic link,
/// the file it names, under the same rules. Anything else (a directory, FIFO, socket, device, a
/// link to one or to nothing, a file that is not a polydem checkpoint) is refused with
/// CheckpointError on every rank, naming the path and what it is; nothing is touched.
std::filesystem::path checkpointTarget(const std::filesystem::path& path, MPI_Comm comm);

/// Reads and verifies `path` (collective; see the top of this file).
sim::CheckpointData readCheckpoint(const std::filesystem::path& path, MPI_Comm comm,
                                   const hdf5::CheckpointIoOptions& options = {});

/// A checkpoint read in two parts, so that a restart never holds a rank's whole share of the pair
/// histories in transit form: opening reads and verifies everything but the histories (data(),
/// its pair and sub-contact tables empty); next() then hands out this rank's share of the pair
/// histories, then of the sub-contact histories, one collective round of the file
/// (CheckpointIoOptions::round_bytes) at a time. Their checksums are verified, and the file is
/// checked for datasets the reader does not know and closed, when next() returns false. Every
/// call is collective; problems are CheckpointErrors naming the file and the dataset.
class CheckpointReader final : public sim::HistoryChunks {
 public:
  CheckpointReader(const std::filesystem::path& path, MPI_Comm comm,
                   const hdf5::CheckpointIoOptions& options = {});
  ~CheckpointReader() override;
  const sim::CheckpointData& data() const;
  bool next(particles::HistoryRecords& chunk) override;
  /// The datasets verified, once next() has returned false.
  const std::vector<hdf5::CheckpointDatasetInfo>& datasets() const { return datasets_; }
  /// Moves data() out (it is empty afterwards).
  sim::CheckpointData takeData();

 private:
  struct Open;
  std::unique_ptr<Open> open_;
  std::vector<hdf5::CheckpointDatasetInfo> datasets_;
  bool done_ = false;
};

/// What `polydem checkpoint info` prints; the same on every rank.
struct CheckpointSummary {
  std::string file;
  int format_version = 0;
  std::uint64_t digest = 0;  // the whole-file digest, verified; 0 for files before version 3
  std::string code_version;
  std::string scene_file;
  std::uint64_t scene_hash = 0;
  std::int64_t step = 0;
  double time = 0.0, dt = 0.0;
  sim::CheckpointStage stage = sim::CheckpointStage::kMain;
  std::int64_t equilibrium_steps = 0;
  bool equilibrium_reached = false;
  std::int64_t particles = 0;             // all particles in the file
  std::int64_t replicated_particles = 0;  // fixed and driven among them
  std::int64_t pairs = 0;                 // pair histories
  std::int64_t touching_pairs = 0;
  int shapes = 0, materials = 0;
  int writer_ranks = 0;
  Vec3 domain_lo = Vec3::Zero(), domain_hi = Vec3::Zero();
  Vec3 particles_lo = Vec3::Zero(), particles_hi = Vec3::Zero();  // centroid bounding box, m
  /// Kinetic energy of the free particles (translation + rotation, J) from the stored leapfrog
  /// velocities, which lag the positions by dt/2; an exact sum, the same on any rank count.
  double kinetic_energy = 0.0;
  std::vector<hdf5::CheckpointDatasetInfo> datasets;
};

/// Reads `path`, verifies every dataset and summarises it (collective). Throws CheckpointError.
CheckpointSummary verifyCheckpoint(const std::filesystem::path& path, MPI_Comm comm);
/// The summary as text: one "key: value" line each, then the datasets with their checksums.
std::string formatCheckpointSummary(const CheckpointSummary& summary);

// --- files in a checkpoint directory (not collective: call on one rank)
// ---------------------------

/// Each run that takes checkpoints has an id, drawn at random when it starts (a continued run
/// gets a new one), in the names of its files: it keeps and deletes only its own checkpoints, so
/// that runs sharing a folder never prune or overwrite each other's (docs/checkpoint.md).
inline constexpr int kCheckpointRunIdDigits = 8;  // lowercase hexadecimal

/// dir / "checkpoint_<step, 12 digits>_<run id>.h5", e.g. checkpoint_000000001500_5f3a09c2.h5.
/// Negative step or a run id of other than 8 lowercase hexadecimal digits: Error.
std::filesystem::path checkpointFileName(const std::filesystem::path& dir, std::int64_t step,
                                         const std::string& run_id);

/// A run id that no file in `dir` carries (a missing directory: any).
std::string newCheckpointRunId(const std::filesystem::path& dir);

struct CheckpointFile {
  std::int64_t step = 0;
  std::string run_id;  // empty: checkpoint_<step>.h5, named before runs had ids
  std::filesystem::path path;
};
/// The regular files in `dir` (not symbolic links) named exactly as checkpointFileName() names
/// them, or checkpoint_<step>.h5, by step (then run id). Temporary files of unfinished writes and
/// every other name are left out. A missing directory: none.
std::vector<CheckpointFile> listCheckpoints(const std::filesystem::path& dir);

/// Deletes all but the `keep` (>= 1) newest checkpoints of run `run_id` in `dir`; no other run's
/// checkpoints and no other file are touched. Returns the deleted paths.
std::vector<std::filesystem::path> pruneCheckpoints(const std::filesystem::path& dir,
                                                    const std::string& run_id, int keep);

/// A temporary file of a checkpoint write: named exactly as a checkpoint of listCheckpoints +
/// ".tmp.<pid>", pid being rank 0's process id of the writer (writeCheckpoint).
struct TemporaryCheckpointFile {
  std::filesystem::path path;
  long pid = 0;
  std::uintmax_t bytes = 0;
  bool writer_alive = false;  // a process with that id runs on this machine (or it is this one)
  bool removed = false;       // by removeStaleTemporaryCheckpoints
};
/// The regular files in `dir` named as writeCheckpoint names its temporary files; every other
/// name is left out.
std::vector<TemporaryCheckpointFile> listTemporaryCheckpoints(const std::filesystem::path& dir);
/// Deletes the temporary files of listTemporaryCheckpoints(dir) whose writer is gone (a write
/// cut short by kill -9 or a crash leaves one); those of a process that still runs on this
/// machine are left. Returns what it found, `removed` telling which are gone.
std::vector<TemporaryCheckpointFile> removeStaleTemporaryCheckpoints(
    const std::filesystem::path& dir);

}  // namespace polydem::checkpoint
