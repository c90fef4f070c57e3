#include "polydem/broadphase/all_pairs.h"

#include "polydem/broadphase/overlap.h"
#include "polydem/broadphase/scene_bounds.h"

namespace polydem::broadphase {

void AllPairs::findPairs(const SphereSet& spheres, double margin, std::vector<CandidatePair>& out) {
  out.clear();
  detail::checkAndBound(spheres, margin);
  const auto n = static_cast<std::int32_t>(spheres.centers.size());
  for (std::int32_t a = 0; a < n; ++a) {
    const Vec3& ca = spheres.centers[a];
    const double ra = spheres.radii[a];
    for (std::int32_t b = a + 1; b < n; ++b) {
      const Vec3& cb = spheres.centers[b];
      if (withinReach(ca.x(), ca.y(), ca.z(), ra, cb.x(), cb.y(), cb.z(), spheres.radii[b],
                      margin)) {
        if ((spheres.active[a] | spheres.active[b]) == 0) continue;
        const bool a_first = spheres.uids[a] < spheres.uids[b];
        out.push_back({a_first ? a : b, a_first ? b : a});
      }
    }
  }
}

}  // namespace polydem::broadphase
