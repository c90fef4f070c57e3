// ParaView snapshots of a parallel run. Every rank writes its own particles as one VTK XML
// PolyData piece (.vtp); rank 0 writes the parallel header (.pvtp) that lists the pieces and keeps
// a collection file (.pvd) of all snapshots with their times, so a person opens
// DIR/snapshots.pvd (particles) or DIR/contacts.pvd (contact points) in ParaView and scrubs
// through time. Layout of DIR:
//
//   snapshots.pvd                                   collection: time -> snapshots/particles_S.pvtp
//   contacts.pvd                                    collection: time -> snapshots/contacts_S.pvtp
//   snapshots/particles_S.pvtp, particles_S_rR.vtp  S = step (10 digits), R = rank (4 digits)
//   snapshots/contacts_S.pvtp,  contacts_S_rR.vtp
//
// A particle is a closed polygon mesh: its world vertices are points of the piece and each face
// is one polygon cell, so the particle's data (uid, rank, velocity, ...) is repeated on each of
// its faces. A contact is one vertex cell at the contact point with its forces as point data.
//
// Binary encoding (the default) is the VTK XML "appended" format with encoding="base64",
// header_type="UInt64", byte order of the host: each array is one base64 block of an 8-byte
// byte count followed by the values, and its `offset` counts base64 characters from the "_"
// that opens the appended data (details in vtk_xml.h). The XML stays well formed; the files are
// about 1.8x smaller than ASCII at full precision and over 10x faster to write. Values are
// written exactly (Float64, no rounding); ASCII (%.17g) is there for debugging.
#pragma once

#include <mpi.h>

#include <cstdint>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "polydem/core/types.h"

namespace polydem::output {

/// The data of one particle in a snapshot. `displacement` is the centroid's displacement since
/// the start of the run; speed (|velocity|) is added by the writer.
struct ParticleFields {
  Uid uid = 0;
  Vec3 velocity = Vec3::Zero();
  Vec3 angular_velocity = Vec3::Zero();
  Vec3 displacement = Vec3::Zero();
  bool fixed = false;
  // Written by the HDF5 snapshots only (output/snapshot_h5.h): the VTK pieces keep their fixed set.
  std::int32_t material = -1;
  Vec3 position = Vec3::Zero();  // centroid
  std::int32_t contact_count = 0;
  Vec3 force = Vec3::Zero();  // resultant contact force
};

/// The polyhedra of one rank, as plain arrays (no dependency on the particle storage). Fill with
/// addParticle() and then addFace() for each face of that particle; clear() keeps the capacity.
struct PolyhedraBatch {
  std::vector<ParticleFields> particles;
  std::vector<Vec3> points;                // world vertices of all particles, particle by particle
  std::vector<std::int64_t> point_end;     // particle p owns points [point_end[p-1], point_end[p])
  std::vector<std::int64_t> connectivity;  // point indices of all faces, face after face
  std::vector<std::int64_t> face_end;      // face f is connectivity[face_end[f-1] .. face_end[f])
  std::vector<std::int64_t> particle_face_end;  // particle p owns faces [..[p-1], ..[p])
  /// Per face: the scene's [[joint]] whose plane made the face (index into Setup::joints), -1
  /// for a face on no joint (a rock mass's free surface, a plane that names no joint, a
  /// [[particle]]'s faces).
  std::vector<std::int32_t> face_joint;
  /// Per face: the mean water pressure on it (Pa, sim/water.h faceWaterPressures), 0 without.
  std::vector<double> face_pressure;

  /// Adds a particle with its vertices in world coordinates; its faces follow with addFace().
  void addParticle(const ParticleFields& fields, std::span<const Vec3> world_vertices);
  /// Adds a face of the last added particle: indices into that particle's vertices, counter-
  /// clockwise seen from outside, made by joint `joint` (-1: none), with the water pressure
  /// `pressure` (Pa) on it. Throws polydem::Error on an index out of range or < 3 vertices.
  void addFace(std::span<const int> vertices, std::int32_t joint = -1, double pressure = 0.0);
  /// A particle with all its faces (each a vector of vertex indices).
  void addParticle(const ParticleFields& fields, std::span<const Vec3> world_vertices,
                   const std::vector<std::vector<int>>& faces);
  void clear();

  std::size_t particleCount() const { return particles.size(); }
  std::size_t faceCount() const { return face_end.size(); }
};

/// One contact as seen from particle A (the lower uid): the force on A is
/// normal_force * normal + shear_force; `normal` points from B into A.
struct ContactRecord {
  Uid uid_a = 0, uid_b = 0;
  Vec3 point = Vec3::Zero();
  Vec3 normal = Vec3::Zero();
  double normal_force = 0.0;
  Vec3 shear_force = Vec3::Zero();
  std::int32_t joint = -1;  // the [[joint]] whose properties it took, -1: the material pair's
};

struct ContactBatch {
  std::vector<ContactRecord> contacts;
};

enum class VtkEncoding { kBase64, kAscii };

class SnapshotWriter {
 public:
  struct Options {
    VtkEncoding encoding = VtkEncoding::kBase64;
    /// Continuing a run from a checkpoint taken at this step: the collections keep the snapshots
    /// already listed up to and including this step and drop later ones. Unset: a fresh series.
    std::optional<std::int64_t> resume_after_step;
  };

  /// Collective over `comm`: creates `dir` and `dir`/snapshots and writes both collections
  /// (empty on a fresh run, so none left by an earlier run in `dir` outlives this start; trimmed
  /// to the checkpoint when resuming). Throws polydem::Error on all ranks if that fails.
  SnapshotWriter(std::string dir, MPI_Comm comm);
  SnapshotWriter(std::string dir, MPI_Comm comm, Options options);

  /// Collective: every rank writes its piece(s), then rank 0 the .pvtp and the updated .pvd.
  /// `contacts` may be null on some ranks (no contacts there); when it is null on all ranks no
  /// contact snapshot is written. Writing a step again replaces that snapshot. On any failure
  /// every rank throws polydem::Error naming the file, and the collections stay as they were.
  void write(double time, std::int64_t step, const PolyhedraBatch& particles,
             const ContactBatch* contacts);

  std::string particleCollectionPath() const;  // dir/snapshots.pvd
  std::string contactCollectionPath() const;   // dir/contacts.pvd
  /// Path of the .pvtp (rank < 0) or of rank's .vtp of the particle snapshot at `step`.
  std::string particlePath(std::int64_t step, int rank = -1) const;
  std::string contactPath(std::int64_t step, int rank = -1) const;

 private:
  struct Collection {
    std::string path;                                                // the .pvd
    std::map<std::int64_t, std::pair<double, std::string>> entries;  // step -> (time, file)
  };
  void loadCollection(Collection& collection, std::int64_t keep_up_to) const;
  void writeCollection(const Collection& collection) const;

  std::string dir_;
  MPI_Comm comm_;
  int rank_ = 0, size_ = 1;
  Options options_;
  Collection particles_, contacts_;
};

}  // namespace polydem::output
