// Parallel snapshots: one HDF5 file per snapshot, written collectively by all ranks through the
// checkpoints' MPI-IO layer (hdf5/hdf5_file.h), plus two XDMF collections
// (output/xdmf_writer.h) that ParaView opens. A run on P ranks writes 1 file per snapshot instead
// of the VTK output's 2 (1 + P). Layout of DIR:
//
//   snapshots.xmf                   temporal collection of the blocks (open this one)
//   contacts.xmf                    temporal collection of the contact points
//   snapshots/snapshot_S.h5         S = step (10 digits)
//
// A snapshot file (docs/output-files.md has the table):
//
//   /            attributes format = "polydem-snapshot", format_version, step, time,
//                writer_ranks, fields, contact_fields, joint_names
//   /mesh        points (V x 3, world vertices), topology (XDMF Mixed: per face 3, n, n indices)
//   /particles   uid, face_count, position (centroid), velocity: one row per particle, always
//   /faces       the chosen particle fields, one row per face (cell data)
//   /contacts    point, vertex (0..C-1), and the chosen contact fields, one row per contact
//
// Particle, point, face and topology rows are in uid order whatever rank holds a particle (each
// rank writes a union of hyperslabs), so those tables are the same on any rank count; contact
// rows are in rank order.
// The file is written as "snapshot_S.h5.tmp" and renamed when complete; the collections are
// rewritten (atomically, by rank 0) only after that, so they never list a missing file.
#pragma once

#include <mpi.h>

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "polydem/output/vtk_writer.h"
#include "polydem/output/xdmf_writer.h"

namespace polydem::output {

inline constexpr int kSnapshotFormatVersion = 1;

class XdmfSnapshotWriter {
 public:
  struct Options {
    std::vector<std::string> fields;          // names of kParticleFields; empty: the defaults
    std::vector<std::string> contact_fields;  // names of kContactFields; empty: the defaults
    /// The scene's [[joint]] names, in file order: the root attribute joint_names (one per
    /// line), which names the ids of the face and contact field `joint`.
    std::vector<std::string> joint_names;
  };

  /// Collective: creates `dir`/snapshots and writes both collections empty (so none left by an
  /// earlier run in `dir` outlives this start). Throws polydem::Error on all ranks on failure,
  /// and on an unknown field name.
  XdmfSnapshotWriter(std::string dir, MPI_Comm comm, Options options);

  /// Collective: writes the snapshot file of `step`, then rank 0 the collections. `contacts`
  /// may be null (none on this rank). Writing a step again replaces it. On any failure every
  /// rank throws polydem::Error naming the file; the collections stay as they were.
  void write(double time, std::int64_t step, const PolyhedraBatch& particles,
             const ContactBatch* contacts);

  std::string particleCollectionPath() const;  // dir/snapshots.xmf
  std::string contactCollectionPath() const;   // dir/contacts.xmf
  std::string snapshotPath(std::int64_t step) const;

 private:
  /// Writes the snapshot `path` under the name `tmp` (collective).
  void writeFile(const std::string& path, const std::string& tmp, std::int64_t step, double time,
                 const PolyhedraBatch& particles, const ContactBatch& contacts,
                 XdmfSnapshot& counts) const;
  void writeCollections() const;

  std::string dir_;
  MPI_Comm comm_;
  int rank_ = 0, size_ = 1;
  Options options_;
  std::map<std::int64_t, XdmfSnapshot> snapshots_;
};

}  // namespace polydem::output
