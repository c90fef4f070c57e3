// Operator 2 of the contact phase (contact_phase.h): which ordered pairs are evaluated at all.
// The decision is made here, in the pair's canonical frame (A where its owner stores it, B shifted
// by the difference of the two periodic image shifts), never by the broad phase, which only has
// to return a superset: so every rank that sees a pair decides alike. A pair passes if the bounding
// spheres, then the bounding boxes, come within the margin.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "polydem/particles/particle_storage.h"
#include "polydem/sim/pair_order.h"

namespace polydem::sim {

/// A pair placed in its canonical frame, as the kernel gets it.
struct PairFrame {
  Vec3 xa, xb;                   // centroids
  std::span<const Vec3> va, vb;  // world vertices (valid until the next accept())
};

class PairFilter {
 public:
  /// Each particle's bounding box, and whether it has no periodic image shift, once per step.
  void prepare(const particles::ParticleStorage& storage);
  /// Whether `pair` is evaluated with `margin` (absolute); if so, `frame` holds its placement.
  bool accept(const particles::ParticleStorage& storage, const particles::ShapeTable& shapes,
              const OrderedPair& pair, double margin, PairFrame& frame);

 private:
  std::vector<Vec3> box_lo_, box_hi_;    // per storage index, this step
  std::vector<std::uint8_t> unshifted_;  // per storage index: the image shift is zero
  std::vector<Vec3> scratch_a_, scratch_b_;
};

}  // namespace polydem::sim
