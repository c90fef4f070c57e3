// A guard against candidate pairs that cannot fit in memory (particles placed on top of each
// other by mistake: thousands of coincident cubes make millions of pairs), checked before the
// contact phase allocates its per-pair records and histories, so that such a scene ends in a
// message naming the particles instead of std::bad_alloc after minutes of paging.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>

#include "polydem/broadphase/broad_phase.h"
#include "polydem/particles/particle_storage.h"
#include "polydem/setup/setup.h"

namespace polydem::sim {

/// Bytes one candidate pair takes in a step, about: the broad phase's output (with its growth),
/// the contact phase's sorted copy and record, and the pair history in the old and new tables.
std::size_t bytesPerCandidatePair();

/// Empty if `candidates` fit in `available` bytes; otherwise the message: how many pairs, how
/// much memory, and the particle with the most candidate partners with its nearest partner and
/// their lines in the scene file, and the cause: particles on top of each other, or (when even
/// the nearest partner lies beyond both bounding spheres) the contact margin `margin` (m) that
/// reaches across the gaps. `radii`: circumradius of each particle of the storage. `step`
/// labels the message.
std::optional<std::string> pairMemoryProblem(const setup::Setup& scene,
                                             const particles::ParticleStorage& storage,
                                             std::span<const double> radii, double margin,
                                             std::span<const broadphase::CandidatePair> candidates,
                                             std::int64_t step, std::uint64_t available);

}  // namespace polydem::sim
