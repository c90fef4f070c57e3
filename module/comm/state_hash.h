// A hash of the whole simulation state, the same on any rank count: particles are hashed in uid
// order, pair histories in key order. `polydem run` writes it into summary.json as "state_hash",
// so that two runs (1 vs 4 ranks, restarted vs uninterrupted) can be compared bit for bit.
#pragma once

#include <mpi.h>

#include <cstdint>
#include <string>

#include "polydem/particles/contact_history.h"
#include "polydem/particles/particle_storage.h"

namespace polydem::comm {

struct StateHash {
  std::uint64_t particles = 0;  // over uid, shape, material, flags, pose, velocities
  std::uint64_t history = 0;    // over every pair's key and history
  std::uint64_t combined = 0;
  std::int64_t particle_count = 0;
  std::int64_t pair_count = 0;
  // Two ranks holding different bits for the same pair: a determinism bug. Must stay 0.
  std::int64_t history_conflicts = 0;
  std::string hex() const;
};

/// Collective; every rank gets the same result.
StateHash globalStateHash(const particles::ParticleStorage& storage,
                          const particles::ContactHistory& history, MPI_Comm comm);

/// Hash of one particle's persistent state (ghost flag excluded).
std::uint64_t particleHash(const particles::Particle& p);

}  // namespace polydem::comm
