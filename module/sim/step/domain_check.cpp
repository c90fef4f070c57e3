// Operator "domain check": a free particle whose state is no longer finite, or that left the
// domain, ends the run with the scene file and the particle's line in the message (the exchange
// would stop it too, but knows nothing of the scene).
#include <string>

#include "polydem/core/error.h"
#include "polydem/core/strings.h"
#include "polydem/sim/step/operators.h"

namespace polydem::sim {

void checkDomain(StepState& s) {
  const std::int64_t step = s.loop.step() + 1;  // the particles are at its positions
  const auto& box = s.forest->domain();
  for (std::size_t i = 0; i < s.storage.localCount(); ++i) {
    const auto& p = s.storage[i];
    if (!p.isFree()) continue;
    const bool finite = p.position.allFinite() && p.velocity.allFinite() &&
                        p.angular_momentum.allFinite() && p.orientation.coeffs().allFinite();
    if (finite && s.forest->blockOf(s.forest->wrap(p.position)) >= 0) continue;
    const std::string where = p.uid >= 1 && p.uid <= s.scene.particles.size()
                                  ? cat(s.scene.file, ":", s.scene.particles[p.uid - 1].line, ": ")
                                  : cat(s.scene.file, ": ");
    if (!finite) {
      throw SimulationError(cat(where, "particle ", p.uid, " has a state that is no longer finite ",
                                "at step ", step, " (position (", p.position.transpose(),
                                "), velocity (", p.velocity.transpose(), ")): forces or ",
                                "velocities overflowed; check gravity, densities, stiffnesses and ",
                                "dt in the scene"));
    }
    throw SimulationError(cat(where, "particle ", p.uid, " left the domain at (", p.position.x(),
                              ", ", p.position.y(), ", ", p.position.z(), ") at step ", step,
                              "; the domain is [", box.lo.x(), ", ", box.hi.x(), "] x [",
                              box.lo.y(), ", ", box.hi.y(), "] x [", box.lo.z(), ", ", box.hi.z(),
                              "]: enlarge [domain] min/max in the scene"));
  }
}

}  // namespace polydem::sim
