// P-PILE (BENCHMARKS.md): a pile of convex polyhedra settling in a box, generated in code so that
// benchmarks and tests can ask for any particle count. Particles start on a lattice slightly
// apart, randomly turned, and fall onto a floor between four walls.
//
// The wide-floor variant (floor_width > 0) drops the walls and puts the pile in the middle of a
// floor floor_width times as wide as the pile, and leaves the [domain] box to its default (the
// bounding box of all bodies, inflated): the scene on which blocks sized from the domain box
// leave the whole pile in a few blocks.
#pragma once

#include <cstdint>
#include <string>

#include "polydem/setup/setup.h"

namespace polydem::sim {

struct PileOptions {
  std::int64_t particles = 20000;
  std::string shapes = "mixed";  // "mixed": cubes, tetrahedra, octahedra, random polyhedra of
                                 // 8, 16 and 40 vertices; "cubes": aligned unit cubes
  std::string kernel = "gjk-epa-ipm";
  std::int64_t layers = 10;  // lattice layers; the footprint is square
  double gap = 0.05;         // lattice gap, relative to the particle size
  std::uint64_t seed = 1;
  std::int64_t steps = 200;
  double initial_speed = 0.0;  // random initial velocities up to this (m/s)
  double floor_width = 0.0;    // > 0: no walls, a floor this many times as wide as the pile,
                               // and the default [domain] box
};

setup::Setup makePileScene(const PileOptions& options);

/// Thickness of the P-PILE box's floor and walls, m.
inline constexpr double kPileBoxThickness = 1.0;

/// The P-PILE box around the footprint [0, width]^2, shared with the Yade comparison's scene:
/// the shapes floor (reaching `rim` beyond the footprint on every side), wall_x and wall_y, and
/// their fixed particles with uids from `uid` on; with `walls`, four walls up to `height` and the
/// [domain] box just around them, else the floor alone. Returns the next free uid.
Uid addPileBox(setup::Setup& s, double width, double height, double rim, bool walls, Uid uid);

}  // namespace polydem::sim
