// Check kinds on the motion of many blocks at once (parameters in docs/scene-format.md):
//   free_motion    a FreeMotion statistic of the free blocks (or those of a label prefix): mean or
//                  largest displacement or speed, largest angular speed, front advance along a
//                  direction; at the end, its largest value after a given time, or the first time
//                  it falls below a limit after a given time. Its value now is
//                  a column of series.csv (the displacement history of a runout).
//   tilt_failure   blocks on a tilting platform (Zhao section 5.3): the platform's tilt (deg) when
//                  a block first moves `threshold` against the platform, or (measure = "rotation")
//                  the largest rotation (deg) against the platform of the block that has moved
//                  `reach`: near 0 when the slope slides, large when it topples.
//   pair_separation  the first time two particles that pressed on each other stop (Zhao 5.4).
#pragma once

#include <memory>

#include "polydem/run/checks.h"
#include "polydem/run/tracker.h"
#include "polydem/setup/setup.h"

namespace polydem::run {

/// The check of one of the kinds above, or nullptr when `spec.kind` is none of them. Throws
/// InputError (the check's line) for a missing or wrong parameter.
std::unique_ptr<Check> makeMotionCheck(const setup::Setup& scene, const setup::CheckSpec& spec,
                                       Tracker& tracker);

/// The kinds makeMotionCheck knows, for messages.
inline constexpr const char* kMotionCheckKinds = "free_motion, tilt_failure, pair_separation";

}  // namespace polydem::run
