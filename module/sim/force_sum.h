// Operator 6 of the contact phase (contact_phase.h): force summation. A pair's force goes to the
// local free copies of A and B (B gets minus A's force). The phase visits pairs in key order, so
// each particle's forces are added in the order of its partners' uids: the same sum, bit for bit,
// on every rank count.
#pragma once

#include <cstdint>
#include <vector>

#include "polydem/dynamics/monitors.h"
#include "polydem/sim/pair_law.h"

namespace polydem::sim {

/// Adds `r` to forces[local_a] and forces[local_b] (an index < 0: that body is not a local free
/// particle here). xa, xb: the centroids of the canonical frame.
inline void sumPairForce(std::vector<dynamics::ForceAccumulator>& forces, std::int32_t local_a,
                         std::int32_t local_b, const PairLawResult& r, const Vec3& xa,
                         const Vec3& xb) {
  if (!r.touching) return;
  if (r.split) {
    if (local_a >= 0) forces[local_a].addPair(r.force, r.torque_a);
    if (local_b >= 0) forces[local_b].addPair(-r.force, r.torque_b);
  } else {
    if (local_a >= 0) forces[local_a].addContact(r.force, r.point, xa);
    if (local_b >= 0) forces[local_b].addContact(-r.force, r.point, xb);
  }
}

}  // namespace polydem::sim
