// Changes of a running simulation's state between steps, made by a driving program (Python):
// they act on what a step reads and a checkpoint stores, so a run changed this way continues
// with the same bits on any rank count and after a restart.
#include <cmath>

#include "polydem/core/error.h"
#include "polydem/core/mpi_env.h"
#include "polydem/core/strings.h"
#include "polydem/dynamics/integrator.h"
#include "polydem/sim/simulation.h"
#include "polydem/sim/step/operators.h"

namespace polydem::sim {

namespace {

void requireFinite(const std::optional<Vec3>& v, const char* what, Uid uid) {
  if (v && !v->allFinite()) {
    throw Error(cat("particle ", uid, ": the ", what, " (", v->transpose(), ") is not finite"));
  }
}

}  // namespace

bool Simulation::setVelocity(Uid uid, const std::optional<Vec3>& velocity,
                             const std::optional<Vec3>& angular_velocity) {
  requireBetweenSteps("setVelocity");
  requireFinite(velocity, "velocity", uid);
  requireFinite(angular_velocity, "angular velocity", uid);
  // How far the new values move the particle's centroid (|v| dt) and its farthest point about
  // the centroid (|w| r dt) in one step; the owner knows r, every rank learns both.
  std::ptrdiff_t index = -1;
  double linear = 0.0, angular = 0.0;
  for (std::size_t i = 0; i < state_.storage.localCount(); ++i) {
    const auto& p = state_.storage[i];
    if (p.uid != uid || !p.isFree()) continue;
    index = static_cast<std::ptrdiff_t>(i);
    if (velocity) linear = velocity->norm() * dt();
    if (angular_velocity)
      angular = angular_velocity->norm() * state_.shapes[p.shape].circumradius * dt();
  }
  if (!mpi::allreduceOr(index >= 0, state_.comm)) return false;
  linear = mpi::allreduceMax(linear, state_.comm);
  angular = mpi::allreduceMax(angular, state_.comm);
  const auto refuse = [&](const char* what, const Vec3& value, double reach, const char* rule) {
    throw Error(cat("particle ", uid, ": the ", what, " (", value.transpose(), ") would move it ",
                    reach, " m in one step (", rule, ", dt = ", dt(), " s), more than ",
                    stepReach(), " m, the farthest a particle may move in one ",
                    "step (the largest free circumradius plus the contact margin)"));
  };
  if (!(linear <= stepReach())) refuse("velocity", *velocity, linear, "|v| dt");
  if (!(angular <= stepReach())) {
    refuse("angular velocity", *angular_velocity, angular, "|w| r dt, r its circumradius");
  }
  if (index >= 0) {
    auto& p = state_.storage[static_cast<std::size_t>(index)];
    if (velocity) p.velocity = *velocity;
    // The leapfrog keeps the angular momentum; L = R I R^T w at the current orientation.
    if (angular_velocity) {
      p.angular_momentum = dynamics::angularMomentum(
          p.orientation, *angular_velocity,
          massProperties(static_cast<std::size_t>(index)).principal_inertia);
    }
  }
  // Ghost copies carry velocities into the contact law's damping: refresh them (collective).
  refreshGhosts(state_);
  return true;
}

}  // namespace polydem::sim
