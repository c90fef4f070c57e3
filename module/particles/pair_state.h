// A contact kernel's memory of one pair between steps (its warm start). The kernels
// (module contact) read and write it; the contact history (contact_history.h) stores it with the
// pair, migrates it with the particles and writes it to checkpoints, so it lives with the storage.
#pragma once

#include <cstdint>

#include "polydem/core/types.h"

namespace polydem::particles {

/// Per-pair memory kept between steps. Plain data, so it can be sent and checkpointed as bytes.
struct PairState {
  Vec3 warm_direction = Vec3::Zero();  // GJK: last separating axis; FCP: last common-plane normal
  Vec3 warm_point = Vec3::Zero();      // FCP: a point on the last common plane
  std::uint32_t warm_valid = 0;        // 1 if the warm start may be used
  std::uint32_t reserved = 0;
};

}  // namespace polydem::particles
