// Check kind "max_contact_force": the largest contact force between free particles across `axis`
// (its component along the axis left out; default: gravity's direction), over the free
// particles' mean weight.
#include <algorithm>
#include <limits>

#include "polydem/core/exact_sum.h"
#include "polydem/core/mpi_env.h"
#include "polydem/core/strings.h"
#include "polydem/run/checks/final_check.h"
#include "polydem/run/checks/kinds.h"
#include "polydem/run/checks/params.h"
#include "polydem/sim/simulation.h"

namespace polydem::run::kinds {

namespace {

double largestForce(sim::Simulation& sim, const std::optional<Vec3>& axis, std::string& note) {
  const Vec3 down = axis ? *axis : sim.scene().gravity.normalized();
  double largest = 0.0, weight = 0.0;
  std::int64_t free_particles = 0;
  const auto& storage = sim.particles();
  for (std::size_t i = 0; i < storage.localCount(); ++i) {
    if (!storage[i].isFree()) continue;
    weight += sim.massProperties(i).mass * sim.scene().gravity.norm();
    ++free_particles;
  }
  for (const auto& r : sim.contacts().records()) {
    if (!r.touching || !r.both_free) continue;  // between two free particles
    largest = std::max(largest, (r.force - r.force.dot(down) * down).norm());
  }
  // A pair across two ranks is evaluated on both with equal results: the max is unaffected.
  largest = mpi::allreduceMax(largest, sim.comm());
  ExactSum w;
  w += weight;
  w.allreduce(sim.comm());
  const auto n = mpi::allreduceSum(free_particles, sim.comm());
  const double mean_weight =
      n > 0 ? w.value() / static_cast<double>(n) : std::numeric_limits<double>::quiet_NaN();
  note =
      cat("largest contact force across the axis ", largest, " N; mean weight ", mean_weight, " N");
  return largest / mean_weight;
}

}  // namespace

std::unique_ptr<Check> maxContactForce(const setup::Setup& scene, const setup::CheckSpec& spec,
                                       Tracker&) {
  const auto axis = Params(scene, spec).vector("axis");
  return std::make_unique<FinalCheck>(
      spec,
      [axis](sim::Simulation& sim, std::string& note) { return largestForce(sim, axis, note); },
      /*reads_contacts=*/true);
}

}  // namespace polydem::run::kinds
