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
// (comm/history_routing.h). The whole-file digest (io/checkpoint_digest.h) is verified first, then
// every dataset's checksum, shape and type, and that the file holds no dataset the reader does not
// read; every problem is a CheckpointError naming the file and the dataset.
#pragma once

#include <mpi.h>

#include <array>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "core/exact_sum.h"
#include "core/types.h"
#include "io/scene.h"
#include "particles/contact_history.h"
#include "particles/material.h"
#include "particles/particle.h"
#include "particles/particle_storage.h"

namespace polydem::io {

/// Version of the file layout. Version 2 added sub-contacts (/subcontacts) and the joint
/// stiffnesses (jkn/jks columns), version 3 the whole-file digest (io/checkpoint_digest.h).
/// readCheckpoint() reads versions 1 to 3 and refuses others: a version 1 file continues with the
/// single-point contact model it was written with, and files before version 3 are read on their
/// per-dataset checksums alone, with a warning (docs/checkpoint.md, 'Older files').
inline constexpr int kCheckpointFormatVersion = 3;
inline constexpr int kOldestReadableCheckpointVersion = 1;
inline constexpr int kFirstDigestCheckpointVersion = 3;

/// The stage a run was in (see sim::Stage): the initial-equilibrium stage or the main stage.
enum class CheckpointStage : std::int32_t { kEquilibrium = 0, kMain = 1 };

/// One row of the shape table as stored: the body-frame polyhedron and its mass properties.
/// A restart rebuilds its shapes from the stored scene text (the same code path as the first
/// run) and compares them with these records (shapeMismatch), so that a change in the geometry
/// code or the scene cannot silently alter a continued run.
struct CheckpointShape {
  std::string name;
  std::vector<Vec3> vertices;                 // m, body frame
  std::vector<std::vector<int>> faces;        // vertex indices, counter-clockwise seen from outside
  double volume = 0.0;                        // m^3
  Vec3 principal_moments = Vec3::Zero();      // per unit density, m^5
  double circumradius = 0.0, inradius = 0.0;  // m
};

/// The records of a shape table.
std::vector<CheckpointShape> shapeRecords(const particles::ShapeTable& shapes);
/// Empty if `built` matches the stored records bit for bit (names, vertices, faces, mass
/// properties); otherwise the first difference, e.g. "shape 'cube': vertex 3 differs".
std::string shapeMismatch(const std::vector<CheckpointShape>& stored,
                          const particles::ShapeTable& built);

/// The block forest as the writer had it (domain/block_forest.h).
struct CheckpointDomain {
  Vec3 lo = Vec3::Zero(), hi = Vec3::Zero();  // m
  std::array<int, 3> blocks{1, 1, 1};
  std::array<bool, 3> periodic{false, false, false};
  std::vector<int> rank_map;  // block -> rank, one entry per block (x fastest)
  int ranks = 1;              // rank count of the writer
};

struct CheckpointData {
  // --- replicated: the same on every rank (written from rank 0's copy)
  // ----------------------------
  int format_version = kCheckpointFormatVersion;  // as read; writing always writes the current one
  std::uint64_t digest =
      0;  // as read and verified (io/checkpoint_digest.h); 0 before version 3; ignored on write
  std::string code_version;  // polydem version of the writer
  int writer_ranks = 0;      // as read: the number of ranks that wrote the file (ignored on write)
  std::string scene_toml;    // the scene file's text, verbatim
  std::string scene_file;    // its file name, for messages
  std::uint64_t scene_hash = 0;  // checksumOfBytes(scene_toml): computed by the writer, verified
                                 // by the reader; the scene's identity in summaries

  std::int64_t step = 0;
  double time = 0.0;               // s, rounded from time_digits
  ExactSum::Digits time_digits{};  // the exact simulated time (TimeLoop::exactTime().digits())
  double dt = 0.0;                 // s
  CheckpointStage stage = CheckpointStage::kMain;
  std::int64_t equilibrium_steps = 0;
  bool equilibrium_reached = false;

  std::vector<CheckpointShape> shapes;  // shapeRecords(simulation shapes)
  std::vector<particles::Material> materials;
  std::vector<Scene::Interaction> interactions;  // explicit material pairs
  CheckpointDomain domain;
  std::string run_state;  // opaque JSON (checks, tracker...), stored as given

  // --- distributed ------------------------------------------------------------------------------
  /// Write: this rank's non-ghost particles. Replicated (fixed/driven) particles are written once,
  /// from rank 0; other ranks' copies are skipped. Read: every replicated particle, then this
  /// rank's share of the free particles.
  std::vector<particles::Particle> particles;
  /// Write: this rank's share of the pair histories, each pair on exactly one rank. Read: this
  /// rank's share (slice r of P), in file order.
  std::vector<particles::PairKey> pair_keys;
  std::vector<particles::PairHistory> pair_histories;
  /// The sub-contact histories of those pairs, written and read alike (each with its pair's
  /// writer; read as a slice of their own).
  std::vector<particles::SubKey> sub_keys;
  std::vector<particles::SubHistory> sub_histories;
};

/// Tuning of the parallel I/O.
struct CheckpointIoOptions {
  /// Bytes of a table (all its columns) one rank moves per collective round: the particle and
  /// pair tables are packed from their structs (and hashed) into buffers of this size, block by
  /// cache-sized block, then written with one collective transfer per column; reading mirrors
  /// it. Larger rounds mean fewer collective calls and more memory; every rank takes part in
  /// every round (with no rows once it has none left).
  std::size_t round_bytes = std::size_t{32} << 20;
  /// What the file is, for messages ("checkpoint FILE: ..."); the snapshots reuse this layer.
  std::string kind = "checkpoint";
  /// Flush to disk (MPI_File_sync) before closing: a checkpoint must survive a crash; a snapshot
  /// need not, and the sync is most of the cost of writing a small one.
  bool sync_on_close = true;
};

/// Writes `data` to `path` (collective; see the top of this file). Throws CheckpointError on every
/// rank if any rank fails (invalid data, I/O error, rename); `path` is then left as it was.
void writeCheckpoint(const std::filesystem::path& path, const CheckpointData& data, MPI_Comm comm,
                     const CheckpointIoOptions& options = {});

/// Reads and verifies `path` (collective; see the top of this file).
CheckpointData readCheckpoint(const std::filesystem::path& path, MPI_Comm comm,
                              const CheckpointIoOptions& options = {});

/// One dataset of a checkpoint as verified by the reader.
struct CheckpointDatasetInfo {
  std::string name;                 // e.g. "/particles/position"
  std::vector<std::uint64_t> dims;  // e.g. {N, 3}; {} for a scalar string
  std::uint64_t checksum = 0;       // stored and recomputed (they agree, or the read failed)
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
  CheckpointStage stage = CheckpointStage::kMain;
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
  std::vector<CheckpointDatasetInfo> datasets;
};

/// Reads `path`, verifies every dataset and summarises it (collective). Throws CheckpointError.
CheckpointSummary verifyCheckpoint(const std::filesystem::path& path, MPI_Comm comm);
/// The summary as text: one "key: value" line each, then the datasets with their checksums.
std::string formatCheckpointSummary(const CheckpointSummary& summary);
/// "equilibrium" or "main".
const char* toString(CheckpointStage stage);

/// Closes the HDF5 library before MPI_Finalize, quietly. HDF5 1.10 keeps internal objects it
/// cannot release after it has read damaged metadata, and its own shutdown at MPI_Finalize would
/// then print "HDF5: infinite loop closing library" after polydem's error message; with its
/// error printing off it says nothing. Call once, after the last HDF5 use of the process.
void closeHdf5Library();

// --- files in a checkpoint directory (not collective: call on one rank)
// ---------------------------

/// dir / "checkpoint_<step, 12 digits>.h5", e.g. checkpoint_000000001500.h5. Negative step: Error.
std::filesystem::path checkpointFileName(const std::filesystem::path& dir, std::int64_t step);

struct CheckpointFile {
  std::int64_t step = 0;
  std::filesystem::path path;
};
/// The regular files in `dir` named exactly as checkpointFileName() names them, by step. Temporary
/// files of unfinished writes and every other name are left out. A missing directory: none.
std::vector<CheckpointFile> listCheckpoints(const std::filesystem::path& dir);

/// Deletes all but the `keep` (>= 1) newest checkpoints of listCheckpoints(dir); nothing else is
/// touched. Returns the deleted paths.
std::vector<std::filesystem::path> pruneCheckpoints(const std::filesystem::path& dir, int keep);

/// A temporary file of a checkpoint write: named exactly checkpointFileName(dir, step) +
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

}  // namespace polydem::io
