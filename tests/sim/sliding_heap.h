// The scene the rank-count and restart tests share: a heap of 120 particles thrown together
// (they collide at once and stay in contact) that keeps sliding into a corner under tilted
// gravity, over 16 x 16 x 4 small blocks dealt out cyclically, so that pairs in contact cross
// rank borders together and their tangential histories must travel with them.
#pragma once

#include <array>
#include <string>

#include "generators/pile_scene.h"
#include "polydem/setup/setup.h"

namespace polydem::sim::testing {

/// `shapes` and `gap` as PileOptions has them; the rest is the heap described above.
inline setup::Setup slidingHeap(const std::string& shapes, double gap) {
  PileOptions o;
  o.particles = 120;
  o.layers = 3;
  o.shapes = shapes;
  o.gap = gap;
  o.initial_speed = 3.0;
  o.seed = 11;
  setup::Setup s = makePileScene(o);
  s.dt = 1e-4;
  s.materials[0].friction_angle = 25;
  s.materials[0].normal_damping = 0.1;
  s.materials[0].local_damping = 0.2;
  s.domain.blocks = std::array<int, 3>{16, 16, 4};
  s.domain.balancer = "cyclic";
  s.gravity = Vec3(4.0, 2.5, -9.81);
  return s;
}

}  // namespace polydem::sim::testing
