#include "polydem/broadphase/broad_phase.h"

#include <cmath>
#include <limits>

#include "polydem/broadphase/all_pairs.h"
#include "polydem/broadphase/level_plan.h"
#include "polydem/broadphase/multilevel_grid.h"
#include "polydem/broadphase/nbs_grid.h"
#include "polydem/broadphase/scene_bounds.h"
#include "polydem/core/error.h"
#include "polydem/core/strings.h"

namespace polydem::broadphase {

namespace detail {

SceneBounds checkAndBound(const SphereSet& spheres, double margin) {
  const std::size_t n = spheres.centers.size();
  if (spheres.radii.size() != n || spheres.uids.size() != n || spheres.active.size() != n) {
    throw Error(cat("broad phase: SphereSet arrays differ in length (centers ", n, ", radii ",
                    spheres.radii.size(), ", uids ", spheres.uids.size(), ", active ",
                    spheres.active.size(), ")"));
  }
  if (n > static_cast<std::size_t>(std::numeric_limits<std::int32_t>::max())) {
    throw Error(cat("broad phase: ", n, " particles exceed the 32-bit local index"));
  }
  if (!std::isfinite(margin) || margin < 0.0) {
    throw Error(cat("broad phase: margin ", margin, " must be finite and >= 0"));
  }
  SceneBounds b;
  if (n == 0) return b;
  b.lo = b.hi = spheres.centers[0];
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3& c = spheres.centers[i];
    const double r = spheres.radii[i];
    if (!std::isfinite(c.x()) || !std::isfinite(c.y()) || !std::isfinite(c.z()) ||
        !std::isfinite(r) || r < 0.0) {
      throw Error(cat("broad phase: particle uid ", spheres.uids[i], " has centre (", c.x(), ", ",
                      c.y(), ", ", c.z(), ") and radius ", r,
                      "; need a finite centre and a finite radius >= 0"));
    }
    b.lo = b.lo.cwiseMin(c);
    b.hi = b.hi.cwiseMax(c);
    b.max_radius = std::max(b.max_radius, r);
  }
  return b;
}

void checkParams(const BroadPhaseParams& params) {
  if (!(params.gamma == 0.0 || (params.gamma > 1.0 && std::isfinite(params.gamma)))) {
    throw Error(cat("broad phase: gamma ", params.gamma, " must be 0 (automatic) or > 1"));
  }
  if (params.levels < 0 || params.levels > detail::kMaxLevels) {
    throw Error(
        cat("broad phase: levels ", params.levels, " must be 0 (automatic) .. ", kMaxLevels));
  }
  if (!(params.cell_factor >= 1.0 && std::isfinite(params.cell_factor))) {
    throw Error(cat("broad phase: cell_factor ", params.cell_factor, " must be finite and >= 1"));
  }
}

}  // namespace detail

std::vector<std::string> broadPhaseNames() {
  return {"multilevel", "nbs", "all-pairs"};
}

std::unique_ptr<BroadPhase> makeBroadPhase(std::string_view name, const BroadPhaseParams& params) {
  detail::checkParams(params);
  if (name == "multilevel") return std::make_unique<MultiLevelGrid>(params);
  if (name == "nbs") return std::make_unique<NbsGrid>(params);
  if (name == "all-pairs") return std::make_unique<AllPairs>();
  throw Error(cat("unknown broad phase '", name, "'; known: ", join(broadPhaseNames(), ", ")));
}

}  // namespace polydem::broadphase
