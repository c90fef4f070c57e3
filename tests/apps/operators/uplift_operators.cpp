// A tiny library of force operators for apps_scene_operators (scene_operators_test.py), named in
// its scene by [[operator]]: "uplift" lifts particle 2 with half of its weight under a gravity of
// kG, so that it falls at kG / 2 while particle 1 falls at kG.
#include "polydem/sim/operator_library.h"

namespace {

constexpr double kG = 9.81;  // m/s^2, the scene's gravity (scene_operators_test.py writes it)
constexpr polydem::Uid kLifted = 2;

}  // namespace

POLYDEM_FORCE_OPERATOR(uplift) {
  for (std::size_t i = 0; i < step.forces.size(); ++i) {
    if ((*step.particles)[i].uid != kLifted) continue;
    step.forces[i].addBodyForce(polydem::Vec3(0, 0, 0.5 * kG * step.particles->mass(i)));
  }
}
