// Operator "broadphase": candidate pairs over owned and ghost particles (a superset of the
// contact phase's own test).
#include "polydem/sim/step/operators.h"

#include <algorithm>
#include <new>

#include "polydem/core/error.h"
#include "polydem/core/memory.h"
#include "polydem/core/strings.h"
#include "polydem/sim/pair_memory.h"

namespace polydem::sim {

double fillSphereSet(StepState& s) {
  const std::size_t n = s.storage.size();
  s.centers.resize(n);
  s.radii.resize(n);
  s.uids.resize(n);
  s.active.resize(n);
  double r_max = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    const auto& p = s.storage[i];
    s.centers[i] = s.storage.placedPosition(i);
    s.radii[i] = s.shapes[p.shape].circumradius;
    s.uids[i] = p.uid;
    s.active[i] = i < s.storage.localCount() && p.isFree();
    r_max = std::max(r_max, s.radii[i]);
  }
  return r_max;
}

void findCandidates(StepState& s) {
  findPairs(s, s.candidates);
  // Before the contact phase allocates its records and histories for every pair.
  if (s.candidates.size() * bytesPerCandidatePair() > (std::size_t{64} << 20)) {
    if (const auto problem = pairMemoryProblem(s.scene, s.storage, s.radii, s.margin, s.candidates,
                                               s.loop.step(), availableMemoryBytes())) {
      throw SimulationError(*problem);
    }
  }
}

void findPairs(StepState& s, std::vector<broadphase::CandidatePair>& out) {
  const double r_max = fillSphereSet(s);
  // A superset of the contact phase's own test, which is made in each pair's canonical frame.
  const double margin = s.margin + 1e-9 * 2.0 * r_max;
  try {
    s.broadphase->findPairs({s.centers, s.radii, s.uids, s.active}, margin, out);
  } catch (const std::bad_alloc&) {
    throw SimulationError(cat("step ", s.loop.step(), ": the broad phase ran out of memory for ",
                              "its candidate pairs (", out.size(),
                              " so far): particles overlap massively, or the contact margin of ",
                              s.margin, " m reaches across many of them; check the scene for ",
                              "particles placed on top of each other and its contact_margin"));
  }
}

}  // namespace polydem::sim
