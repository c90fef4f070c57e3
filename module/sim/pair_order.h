// Operator 1 of the contact phase (contact_phase.h): pair canonicalisation. Each candidate pair of
// the broad phase becomes (A, B) with A the lower uid, and the pairs are put in key order
// (lo uid, hi uid, then storage indices), the order in which every later operator visits them
// and in which each particle's forces are summed.
#pragma once

#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include "polydem/broadphase/broad_phase.h"
#include "polydem/particles/contact_history.h"
#include "polydem/particles/particle_storage.h"

namespace polydem::sim {

/// A candidate pair in canonical form.
struct OrderedPair {
  particles::PairKey key;
  std::int32_t a, b;  // storage indices of the lower- and higher-uid particle
};

class PairOrder {
 public:
  /// The pairs of `candidates` (over `storage`) in key order; valid until the next call. Periodic
  /// images can give the same key more than once; such pairs are adjacent.
  std::span<const OrderedPair> sort(const particles::ParticleStorage& storage,
                                    std::span<const broadphase::CandidatePair> candidates);
  /// Heap bytes of the ordered pairs and the sort's arrays (capacities, core/memory.h).
  std::uint64_t heapBytes() const;

 private:
  std::vector<OrderedPair> canonical_;                // in key order
  std::vector<broadphase::CandidatePair> by_hi_;      // (A, B) by the rank of B's uid
  std::vector<std::pair<Uid, std::int32_t>> by_uid_;  // (uid, storage index), sorted
  std::vector<std::int32_t> uid_rank_;                // per storage index: rank of its uid
  std::vector<std::size_t> lo_start_, hi_start_;      // pairs per lower-, higher-uid rank
};

}  // namespace polydem::sim
