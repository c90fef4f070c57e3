// Input checks and bounds shared by the broad-phase methods (internal to the module).
#pragma once

#include "broadphase/broad_phase.h"

namespace polydem::broadphase::detail {

/// Bounds of a SphereSet: the box of the centres and the largest radius.
struct SceneBounds {
  Vec3 lo = Vec3::Zero();
  Vec3 hi = Vec3::Zero();
  double max_radius = 0.0;
  double extent() const { return (hi - lo).maxCoeff(); }
};

/// Checks `spheres` and `margin` (see BroadPhase::findPairs) and returns their bounds in one pass.
/// Throws polydem::Error naming the offending particle's uid.
SceneBounds checkAndBound(const SphereSet& spheres, double margin);

/// Throws polydem::Error if `params` are out of range (see BroadPhaseParams).
void checkParams(const BroadPhaseParams& params);

/// Appends the pair (a, b) in canonical order if one member is active.
inline void emitPair(const SphereSet& s, std::int32_t a, std::int32_t b,
                     std::vector<CandidatePair>& out) {
  if ((s.active[a] | s.active[b]) == 0) return;
  if (s.uids[a] < s.uids[b]) {
    out.push_back({a, b});
  } else {
    out.push_back({b, a});
  }
}

}  // namespace polydem::broadphase::detail
