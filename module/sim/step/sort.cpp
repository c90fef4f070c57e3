// Operator "sort": the local particles into the broad phase's cell order now and then.
#include "polydem/sim/step/operators.h"

#include <algorithm>

namespace polydem::sim {

// Particles sit in storage in creation and arrival order, and the broad phase's grids visit them
// in cell order: past the caches, every gather of a particle and every pair of the contact phase
// waits on memory. At the first step of this Simulation (and of a restart) and every sort_every
// steps, the local particles are put in the cell order of the grid of the smallest free particles
// (broadphase/cell_order.h; for one size, exactly the order the multilevel grid gathers them in).
// Ghosts keep their places. No result changes (contact_phase.h: uid order throughout).
void sortParticles(StepState& s) {
  const std::int64_t every = s.scene.domain.sort_every;
  if (every <= 0 || (s.sort_started && s.loop.step() % every != 0)) return;
  s.sort_started = true;
  const double r_max = fillSphereSet(s);
  double r_min = r_max;
  bool any_free = false;
  for (std::size_t i = 0; i < s.storage.localCount(); ++i) {
    if (!s.active[i]) continue;
    any_free = true;
    r_min = std::min(r_min, s.radii[i]);
  }
  if (!any_free) return;
  // The reach findCandidates() gives the grid of particles of this size (cell_factor 1).
  const double reach = 2.0 * r_min + s.margin + 1e-9 * 2.0 * r_max;
  s.storage.permuteLocals(
      s.cell_order.order({s.centers, s.radii, s.uids, s.active}, s.storage.localCount(), reach));
  ++s.sorts;
}

}  // namespace polydem::sim
