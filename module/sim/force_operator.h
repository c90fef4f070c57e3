// Force operators: forces a user adds to every step without changing the engine (a pore-pressure
// uplift, a seismic body force, a drag), named in the scene's [[operator]]s (sim/scene_operators.h:
// from a shared library, sim/operator_library.h, or supplied by the program running the scene) or
// added with Simulation::addForceOperator from C++ or Simulation.add_force_operator from Python.
//
// Within a step (sim/step/step_list.cpp) the operators run in order, the scene's first (in file
// order), then those added in code in the order they were added,
// each an operator of the step timed under its own name, after the contact forces, gravity, the
// scene's water pressure (sim/water.h) and bolts have been summed and before the force ratio is
// taken and the particles are integrated:
//
//   ... contacts -> body forces -> water -> bolts -> force operators -> force ratio -> integrate
//   ...
//
// An operator sees this rank's own particles only (no ghosts) and adds to their accumulators; a
// force that depends only on the particle's own state then gives the same bits on any number of
// ranks. Forces on fixed or driven particles are ignored (they are not integrated).
#pragma once

#include <functional>
#include <span>
#include <string>

#include "polydem/dynamics/monitors.h"
#include "polydem/particles/particle_storage.h"

namespace polydem::sim {

/// What a force operator is given in one step.
struct ForceStep {
  /// Time of the positions (0 throughout the initial-equilibrium stage). Velocities are the
  /// leapfrog's, at time - dt/2; angular momenta likewise.
  double time = 0.0;
  double dt = 0.0;
  bool equilibrium = false;  // the initial-equilibrium stage is running
  /// The farthest any point of a particle may move in one step (Simulation::stepReach): a force
  /// that alone moves a particle farther breaks the exchange between ranks.
  double reach = 0.0;
  /// Entries 0 .. forces.size() - 1 are this rank's particles (particles[i], mass(i)); only the
  /// free ones (particles[i].isFree()) move.
  const particles::ParticleStorage* particles = nullptr;
  /// forces[i] acts on particles[i]: add a force at the centroid with addBodyForce(f), at a point
  /// with addContact(f, point, centroid). Each contribution also enters the force ratio's
  /// denominator (Keissar eq. 3.2), as gravity does.
  std::span<dynamics::ForceAccumulator> forces;
};

/// A user's force: called once per step on every rank with that rank's particles.
using ForceOperator = std::function<void(const ForceStep&)>;

}  // namespace polydem::sim
