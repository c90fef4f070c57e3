// Operator 2 of the contact phase (contact_phase.h): which ordered pairs are evaluated at all.
// The decision is made here, in the pair's canonical frame (A where its owner stores it, B shifted
// by the difference of the two periodic image shifts), never by the broad phase, which only has
// to return a superset: so every rank that sees a pair decides alike. A pair passes if the bounding
// spheres, then the bounding boxes, come within the margin. The kernel's contact::Body of each
// particle is built here once per step, not per pair (two 3 x 3 rotations copied per pair cost ~60
// instructions of the dense pack's phase, callgrind); only a pair across a periodic image shift
// gets Bodies of its own.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "polydem/contact/contact.h"
#include "polydem/particles/particle_storage.h"
#include "polydem/sim/pair_order.h"

namespace polydem::sim {

/// A pair placed in its canonical frame, as the kernel gets it.
struct PairFrame {
  Vec3 xa, xb;                 // centroids
  const contact::Body *a, *b;  // placed at xa and xb (valid until the next accept())
};

class PairFilter {
 public:
  /// Each particle's bounding box, Body, and whether it has no periodic image shift, once per
  /// step (after the derived state: the Bodies refer to the storage's world vertices).
  void prepare(const particles::ParticleStorage& storage, const particles::ShapeTable& shapes);
  /// Whether `pair` is evaluated with `margin` (absolute); if so, `frame` holds its placement.
  bool accept(const particles::ParticleStorage& storage, const particles::ShapeTable& shapes,
              const OrderedPair& pair, double margin, PairFrame& frame);
  /// Heap bytes of the per-particle boxes and Bodies (capacities, core/memory.h).
  std::uint64_t heapBytes() const;

 private:
  /// The pair's own Bodies (A at its stored place, B at xb, with these world vertices) in frame.
  void placeOwn(const particles::ParticleStorage& storage, const particles::ShapeTable& shapes,
                const OrderedPair& c, const Vec3& xb, std::span<const Vec3> va,
                std::span<const Vec3> vb, PairFrame& frame);

  std::vector<Vec3> box_lo_, box_hi_;    // per storage index, this step
  std::vector<std::uint8_t> unshifted_;  // per storage index: the image shift is zero
  std::vector<contact::Body> bodies_;    // per storage index, at its stored position
  std::vector<Vec3> scratch_a_, scratch_b_;
  contact::Body shifted_a_, shifted_b_;  // a pair across an image shift
};

}  // namespace polydem::sim
