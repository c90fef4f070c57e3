// Input checks and bounds shared by the broad-phase methods (internal to the module).
#pragma once

#include "polydem/broadphase/broad_phase.h"

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

}  // namespace polydem::broadphase::detail
