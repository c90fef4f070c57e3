#include "polydem/sim/pair_memory.h"

#include <algorithm>
#include <limits>
#include <vector>

#include "polydem/core/memory.h"
#include "polydem/core/strings.h"
#include "polydem/particles/contact_history.h"
#include "polydem/sim/contact_phase.h"

namespace polydem::sim {

namespace {

/// "file:line" of the scene entry of particle `uid`, or "" (particles are numbered in file
/// order from 1: scene.particles[uid - 1]).
std::string whereIs(const setup::Setup& scene, Uid uid) {
  if (uid < 1 || uid > scene.particles.size()) return "";
  return cat(scene.file, ":", scene.particles[uid - 1].line);
}

}  // namespace

std::size_t bytesPerCandidatePair() {
  return 2 * sizeof(broadphase::CandidatePair) + sizeof(particles::PairKey) + 8 +
         sizeof(ContactRecord) + 2 * (sizeof(particles::PairKey) + sizeof(particles::PairHistory));
}

std::optional<std::string> pairMemoryProblem(const setup::Setup& scene,
                                             const particles::ParticleStorage& storage,
                                             std::span<const double> radii, double margin,
                                             std::span<const broadphase::CandidatePair> candidates,
                                             std::int64_t step, std::uint64_t available) {
  const double needed =
      static_cast<double>(candidates.size()) * static_cast<double>(bytesPerCandidatePair());
  if (available == 0 || needed <= static_cast<double>(available)) return std::nullopt;
  // The particle with the most partners, and its nearest partner.
  std::vector<std::int64_t> partners(storage.size(), 0);
  for (const auto& c : candidates) {
    ++partners[c.i];
    ++partners[c.j];
  }
  const auto most = static_cast<std::size_t>(std::max_element(partners.begin(), partners.end()) -
                                             partners.begin());
  const Vec3 at = storage.placedPosition(most);
  std::size_t nearest = most;
  double distance = std::numeric_limits<double>::infinity();
  for (const auto& c : candidates) {
    if (static_cast<std::size_t>(c.i) != most && static_cast<std::size_t>(c.j) != most) continue;
    const std::size_t other = static_cast<std::size_t>(c.i) == most ? c.j : c.i;
    const double d = (storage.placedPosition(other) - at).norm();
    if (d < distance) distance = d, nearest = other;
  }
  const Uid a = storage[most].uid, b = storage[nearest].uid;
  const std::string where = whereIs(scene, a);
  const std::string head =
      cat(where, where.empty() ? "" : ": ", "step ", step, ": ", candidates.size(),
          " candidate pairs would need about ", formatBytes(needed), " (", bytesPerCandidatePair(),
          " bytes each), more than the ", formatBytes(available), " of memory available. Particle ",
          a, " at (", at.x(), ", ", at.y(), ", ", at.z(), ") has ", partners[most],
          " candidate partners; the nearest, particle ", b, " (", whereIs(scene, b), "), is ",
          distance, " m from it");
  const double spheres = radii[most] + radii[nearest];
  if (distance <= spheres) {
    return cat(head, ": particles overlap massively. Check the scene for particles placed on top ",
               "of each other.");
  }
  // Pairs are listed within r_i + r_j + margin: beyond the spheres, only the margin reaches.
  return cat(head, ", beyond their bounding spheres (", spheres,
             " m together): no particle overlaps it; the pairs come from the contact margin of ",
             margin, " m ([scene] contact_margin = ", scene.contact_margin,
             " times the largest free particle's circumradius), which reaches across the gaps "
             "between the particles. Reduce contact_margin, or check the scene for a free "
             "particle far larger than the others.");
}

}  // namespace polydem::sim
