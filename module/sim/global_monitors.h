// The global values of a state, the same on every rank: what the progress line, the
// equilibrium stage's stop condition and the Python module's monitors() report.
#pragma once

#include <cstdint>

#include "polydem/sim/step/step_state.h"

namespace polydem::sim {

/// Global values of the current state, the same on every rank.
struct GlobalMonitors {
  double kinetic_energy = 0.0;
  double force_ratio = 0.0;
  std::int64_t contacts = 0;   // touching pairs, each counted once
  std::int64_t particles = 0;  // free particles
  double max_speed = 0.0;
  double mean_speed = 0.0;
};

/// The global monitors of `s` (collective): kinetic energy and speeds of the free particles,
/// touching pairs, the force ratio of the last contact phase (Keissar eq. 3.2).
GlobalMonitors globalMonitors(const StepState& s);

/// The force ratio of the last contact phase alone (collective, one allreduce of the sums the
/// step's force-ratio pass made): the equilibrium stage's stop condition, checked every step,
/// without a pass over the particles. The same value as globalMonitors(s).force_ratio.
double globalForceRatio(const StepState& s);

}  // namespace polydem::sim
