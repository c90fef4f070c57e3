// The persistent state of one particle: what migrates between ranks, what a ghost copy carries,
// and what a checkpoint stores. Everything else about a particle (rotation matrix, world vertices,
// accumulated force) is derived each step and lives in ParticleStorage's per-step arrays.
#pragma once

#include <cstdint>

#include "polydem/core/byte_buffer.h"
#include "polydem/core/types.h"

namespace polydem::particles {

enum Flag : std::uint32_t {
  kGhost = 1u << 0,   // a copy of a particle owned by another rank
  kFixed = 1u << 1,   // never moves (a boundary block)
  kDriven = 1u << 2,  // moves as prescribed by a driver (tilting platform, shaken base)
};

struct Particle {
  Uid uid = 0;
  std::int32_t shape = -1;     // index into the replicated shape table
  std::int32_t material = -1;  // index into the material table
  std::uint32_t flags = 0;
  std::int32_t driver = -1;  // index into the scene's drivers, for kDriven particles

  Vec3 position = Vec3::Zero();         // centroid, world frame
  Quat orientation = Quat::Identity();  // body -> world
  // Leapfrog state: velocities are taken half a step behind the positions (t - dt/2).
  Vec3 velocity = Vec3::Zero();          // of the centroid
  Vec3 angular_momentum = Vec3::Zero();  // about the centroid, world frame

  bool isGhost() const { return flags & kGhost; }
  bool isFixed() const { return flags & kFixed; }
  bool isDriven() const { return flags & kDriven; }
  /// Fixed and driven particles are replicated on every rank (waLBerla's "global" bodies): each
  /// rank moves them identically, they are never ghosted nor migrated.
  bool isGlobal() const { return flags & (kFixed | kDriven); }
  /// Moved by forces: neither fixed nor driven.
  bool isFree() const { return !isGlobal(); }
};

void pack(SendBuffer& out, const Particle& p);
void unpack(RecvBuffer& in, Particle& p);

}  // namespace polydem::particles
