// The P-BROADPHASE scene (Zhao section 5.5, table 7): cubes of two sizes, 1.0 m and 0.1 m edge,
// settled in a dense random layer on the ground, "dropped from 2.5 mm": every cube sits a few
// millimetres from its neighbours and from the ground. Positions are generated, not simulated:
// each cube gets its own slot of a lattice and is jittered inside it, so no two cubes overlap and
// the scene is the same on every machine (own generator arithmetic, no std distributions).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "polydem/broadphase/broad_phase.h"

namespace polydem::bench {

struct CubeLayerSpec {
  int n = 1000;               // number of cubes
  double big_fraction = 0.1;  // share of big cubes by count
  // "pockets": a layer two big slots high; each slot holds a big cube or a pocket of up to
  //            9 x 9 x 9 small cubes (the small cubes lie in clusters among the big ones);
  // "sprinkle": big cubes on a lattice whose 0.1 m gaps hold the small cubes, scattered at
  //             random in those gaps (every small cube next to big ones).
  std::string layout = "pockets";
  double gap = 2.5e-3;   // clearance between neighbours and above the ground (m)
  bool shuffle = false;  // store the cubes in random order instead of slot order
  // Store the cubes in the order of their cells of the small cubes' size, (z, y, x) as the grid
  // sorts them (broadphase::CellOrder): as a simulation sorts its particles (domain.sort_every).
  bool sort_cells = false;
  bool ground = false;  // add the ground slab as one huge fixed body
  std::uint64_t seed = 2024;
};

struct CubeLayer {
  std::vector<Vec3> centers;
  std::vector<double> radii;  // circumradius: edge * sqrt(3) / 2
  std::vector<Uid> uids;
  std::vector<std::uint8_t> active;
  int big = 0, small = 0;
  broadphase::SphereSet view() const { return {centers, radii, uids, active}; }
};

/// Throws polydem::Error for a spec that cannot be built (n < 1, fraction outside [0, 1],
/// unknown layout).
CubeLayer makeCubeLayer(const CubeLayerSpec& spec);

}  // namespace polydem::bench
