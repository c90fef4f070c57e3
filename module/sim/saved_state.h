// The state a run saves to continue bit for bit, on the same or another number of ranks: what
// Simulation::checkpoint() fills and the restarting constructor takes back. It is the engine's own
// type; the checkpoint module (above the engine) stores it in HDF5 and verifies it
// (checkpoint/checkpoint.h, docs/checkpoint.md), so the engine does not depend on the file format.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "polydem/core/exact_sum.h"
#include "polydem/core/types.h"
#include "polydem/dynamics/bolt_law.h"
#include "polydem/particles/contact_history.h"
#include "polydem/particles/material.h"
#include "polydem/particles/particle.h"
#include "polydem/particles/particle_storage.h"
#include "polydem/setup/setup.h"

namespace polydem::sim {

/// Rows of a contact history a rank writes, without a copy: the pairs at `pairs` (indices into
/// `table`, increasing), each with its block of sub-contacts.
struct HistoryView {
  const particles::ContactHistory* table = nullptr;
  std::vector<std::uint32_t> pairs;
  std::size_t subCount() const {
    std::size_t n = 0;
    for (std::uint32_t k : pairs) {
      const auto [first, last] = table->subsOf(k);
      n += last - first;
    }
    return n;
  }
};

/// The stage a run was in (see sim::Stage): the initial-equilibrium stage or the main stage.
enum class CheckpointStage : std::int32_t { kEquilibrium = 0, kMain = 1 };

/// "equilibrium" or "main".
const char* toString(CheckpointStage stage);

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
  // Per face: the joint plane it lies on, -1: none (geometry::BodyShape::face_plane). A restart
  // takes these over the rebuilt shapes' (the run continues with the joints it had); absent in
  // files before layout version 4, where it continues without joints, as it was written.
  std::optional<std::vector<std::int32_t>> face_plane;
};

/// The records of a shape table.
std::vector<CheckpointShape> shapeRecords(const particles::ShapeTable& shapes);
/// Empty if `built` matches the stored records bit for bit (names, vertices, faces, mass
/// properties; the faces' joint planes are the stored ones, see restoreFacePlanes); otherwise the
/// first difference, e.g. "shape 'cube': vertex 3 differs".
std::string shapeMismatch(const std::vector<CheckpointShape>& stored,
                          const particles::ShapeTable& built);

/// Gives `built` the stored faces' joint planes (none where the file has none); throws
/// CheckpointError, naming `file`, for a plane index outside [-1, planes).
void restoreFacePlanes(const std::vector<CheckpointShape>& stored, particles::ShapeTable& built,
                       std::size_t planes, const std::string& file);

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
  int format_version = 0;    // as read (checkpoint.h: kCheckpointFormatVersion); writing ignores it
  std::uint64_t digest = 0;  // as read and verified (hdf5/file_digest.h); 0 before
                             // version 3; ignored on write
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
  std::vector<setup::Setup::Interaction> interactions;  // explicit material pairs
  CheckpointDomain domain;
  std::string run_state;  // opaque JSON (checks, tracker...), stored as given
  /// The state of every [[bolt]] at every joint it crosses (sim/bolts.h: bolts in file order,
  /// joints from each bolt's start); replicated. Empty for a scene without bolts and in files
  /// before layout version 6.
  std::vector<dynamics::BoltJointState> bolt_states;

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
  /// Write only, instead of the four tables above (Simulation::checkpointForWriting): this rank's
  /// pair histories left in the simulation's table, which a writer reads row by row, so that a
  /// checkpoint holds no copy of the history. Valid until the simulation steps.
  HistoryView history_view;
};

}  // namespace polydem::sim
