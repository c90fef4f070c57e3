// A kinematic driver's prescription (dynamics/driver.h moves the particle): part of the engine's
// setup, kept here so that the driver code does not depend on the setup or the scene file.
#pragma once

#include <string>

#include "polydem/core/types.h"

namespace polydem::dynamics {

/// Prescribed motion of a driven particle (a tilting platform, a shaken base). The velocity of a
/// material point x of the body is v(t) + w(t) x (x - pivot(t)), where the pivot moves with v(t).
struct DriverSpec {
  std::string name;                      // as referenced by [[particle]] driver = "..."
  Vec3 velocity = Vec3::Zero();          // constant part of v
  Vec3 angular_velocity = Vec3::Zero();  // w, rad/s (scene files give deg/s or rad/s: see reader)
  Vec3 pivot = Vec3::Zero();             // at t = start_time
  Vec3 oscillation = Vec3::Zero();  // v += oscillation * sin(2 pi frequency (t - start) + phase)
  double frequency = 0.0;           // Hz
  double phase = 0.0;               // rad
  double start_time = 0.0;          // no motion before
  double end_time = 1e300;          // no motion after
  int line = 0;                     // where a scene file defined it, for messages (0: not a file)
};

}  // namespace polydem::dynamics
