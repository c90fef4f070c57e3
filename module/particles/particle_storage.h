// ParticleStorage: the particles a rank knows (its own, the replicated fixed/driven bodies, and
// ghost copies of neighbours' particles) with their per-step derived data.
//
// The persistent state is an array of Particle (what migrates and is checkpointed); derived data
// (rotation matrices, angular velocities, world vertices, accumulated forces) is kept in parallel
// arrays recomputed every step. Local particles come first, ghosts after them, so that refreshing
// the ghosts each step is a truncate-and-append. No result depends on the storage order: pairs
// are processed in uid order (see sim/), so storage may be reordered freely.
#pragma once

#include <cstdint>
#include <span>
#include <unordered_map>
#include <vector>

#include "polydem/geometry/body_shape.h"
#include "polydem/particles/particle.h"

namespace polydem::particles {

using ShapeTable = std::vector<geometry::BodyShape>;

class ParticleStorage {
 public:
  std::size_t size() const { return state_.size(); }
  /// Owned and global particles (everything that is not a ghost): indices [0, localCount()).
  std::size_t localCount() const { return local_count_; }
  std::size_t ghostCount() const { return state_.size() - local_count_; }

  Particle& operator[](std::size_t i) { return state_[i]; }
  const Particle& operator[](std::size_t i) const { return state_[i]; }
  const std::vector<Particle>& all() const { return state_; }

  /// Index of the local (non-ghost) particle with this uid, or -1. Ghosts are not indexed: across a
  /// periodic boundary a rank may hold a ghost image of one of its own particles.
  int indexOf(Uid uid) const;

  /// Adds a local (non-ghost) particle; ghosts must have been dropped first. Returns its index.
  int addLocal(const Particle& p);
  /// Removes local particle i (the last local particle takes its place); ghosts must be dropped.
  void removeLocal(std::size_t i);
  /// Appends a ghost copy (the kGhost flag is set here). `shift` is the periodic image offset: the
  /// ghost stands at p.position + shift (zero without periodic boundaries). The stored position
  /// stays the owner's bits, so that every rank can rebuild any pair in one canonical frame.
  int addGhost(Particle p, const Vec3& shift = Vec3::Zero());
  void dropGhosts();
  /// Puts the local particles in the order `order` gives: the particle at index order[k] moves to
  /// index k (`order` is a permutation of [0, localCount())); ghosts keep their places. What is
  /// indexed by uid follows. The per-step derived data is left in the old order, as after a
  /// migration: it is valid again after the next updateDerived(). No allocation once warm.
  /// Throws polydem::Error if `order` is not such a permutation.
  void permuteLocals(std::span<const std::int32_t> order);

  /// Recomputes rotation matrices, angular velocities, world vertices (at the placed position)
  /// and world face normals of every particle.
  void updateDerived(const ShapeTable& shapes, std::span<const double> densities);

  /// Heap bytes (capacities, core/memory.h) of the particles' state and uid index, and of the
  /// per-step derived arrays (rotations, world vertices and face normals: the kernels' caches).
  std::uint64_t stateBytes() const;
  std::uint64_t derivedBytes() const;

  // Per-step derived data, parallel to all(); valid after updateDerived().
  /// Periodic image offset of entry i (zero for local particles).
  const Vec3& shift(std::size_t i) const { return shift_[i]; }
  /// Where entry i stands in this rank's frame: position + shift.
  Vec3 placedPosition(std::size_t i) const { return state_[i].position + shift_[i]; }
  const Mat3& rotation(std::size_t i) const { return rotation_[i]; }
  const Vec3& angularVelocity(std::size_t i) const { return angular_velocity_[i]; }
  double mass(std::size_t i) const { return mass_[i]; }
  /// Driven particles get their angular velocity from their driver, not from a momentum.
  void setAngularVelocity(std::size_t i, const Vec3& w) { angular_velocity_[i] = w; }
  std::span<const Vec3> worldVertices(std::size_t i) const {
    return {world_vertices_.data() + vertex_begin_[i], vertex_begin_[i + 1] - vertex_begin_[i]};
  }
  /// World outward face normals of entry i (rotation * shape normal), in the shape's face order.
  std::span<const Vec3> worldFaceNormals(std::size_t i) const {
    return {world_face_normals_.data() + face_begin_[i], face_begin_[i + 1] - face_begin_[i]};
  }

 private:
  std::vector<Particle> state_;
  std::size_t local_count_ = 0;
  std::unordered_map<Uid, int> index_of_;
  std::vector<Vec3> shift_;
  std::vector<Particle> permuted_;    // permuteLocals() scratch
  std::vector<std::uint8_t> placed_;  // permuteLocals() check

  std::vector<Mat3> rotation_;
  std::vector<Vec3> angular_velocity_;
  std::vector<double> mass_;
  std::vector<Vec3> world_vertices_;
  std::vector<std::size_t> vertex_begin_;
  std::vector<Vec3> world_face_normals_;
  std::vector<std::size_t> face_begin_;
};

/// Angular velocity from angular momentum: w = R I^-1 R^T L, I the body-frame principal moments.
inline Vec3 angularVelocityOf(const Mat3& rotation, const Vec3& principal_inertia,
                              const Vec3& angular_momentum) {
  const Vec3 body = rotation.transpose() * angular_momentum;
  return rotation * body.cwiseQuotient(principal_inertia);
}

}  // namespace polydem::particles
