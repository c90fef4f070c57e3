// Each particle's touching contacts and resultant contact force from the last contact phase, for
// the particles this rank owns now (the snapshot's contact_count and force fields).
#pragma once

#include <cstdint>
#include <vector>

#include "polydem/sim/simulation.h"

namespace polydem::run {

/// Fills count[i] and force[i] for every local particle i of sim.particles(). The contact
/// records hold the storage indices of the contact phase, which the exchange at the end of the
/// step invalidates (particles leave and arrive), so the sums are taken by uid: a particle's
/// contacts are summed, in key order, on the rank that owned it during the contact phase, and
/// the sums of particles that have since migrated are sent to their new owners. The result is
/// the same on any rank count. Collective.
void sumContactsByParticle(const sim::Simulation& sim, std::vector<std::int32_t>& count,
                           std::vector<Vec3>& force);

}  // namespace polydem::run
