// What the collective HDF5 layer (hdf5_file.h) is told and what it reports back: the I/O tuning
// of a file it writes or reads, and each dataset it verified. Checkpoints and parallel snapshots
// both write through the layer; `kind` names which one a message is about.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace polydem::hdf5 {

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

/// One dataset of a checkpoint as verified by the reader.
struct CheckpointDatasetInfo {
  std::string name;                 // e.g. "/particles/position"
  std::vector<std::uint64_t> dims;  // e.g. {N, 3}; {} for a scalar string
  std::uint64_t checksum = 0;       // stored and recomputed (they agree, or the read failed)
};

}  // namespace polydem::hdf5
