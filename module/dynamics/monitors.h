// Monitors: the kinetic energy of a particle, a per-particle force accumulator, and the force ratio
// R of Keissar eq. 3.2 that ends the initial-equilibrium stage (Keissar section 3.3, "Static
// Multi-particle Test"; Itasca 3DEC), summed exactly so that R has the same bits on any rank count.
#pragma once

#include <mpi.h>

#include <cmath>

#include "polydem/core/exact_sum.h"
#include "polydem/core/types.h"
#include "polydem/dynamics/integrator.h"
#include "polydem/particles/particle.h"

namespace polydem::dynamics {

/// Kinetic energy 0.5 m v.v + 0.5 L.w (translation + rotation), in J.
inline double kineticEnergy(double mass, const Vec3& velocity, const Vec3& angular_momentum,
                            const Vec3& angular_velocity) {
  return 0.5 * (mass * velocity.squaredNorm() + angular_momentum.dot(angular_velocity));
}

/// Kinetic energy of a free particle from its state (velocities at the leapfrog half step t - dt/2,
/// the angular velocity taken with the orientation at t). Zero for fixed and driven particles,
/// whose motion is prescribed.
double kineticEnergy(const particles::Particle& p, const MassProperties& mass);

/// The "Manhattan norm" <f> = |f_x| + |f_y| + |f_z| of Keissar eq. 3.3.
inline double manhattan(const Vec3& f) {
  return std::abs(f.x()) + std::abs(f.y()) + std::abs(f.z());
}

/// The forces on one particle in one step: their sum, their torque about the centroid and the sum
/// of their Manhattan norms (the particle's term of the denominator of Keissar eq. 3.2). Add the
/// contributions in a fixed order (partners by uid) for bit-for-bit reproducibility.
struct ForceAccumulator {
  Vec3 force = Vec3::Zero();
  Vec3 torque = Vec3::Zero();
  double norm_sum = 0.0;

  /// A contact force acting at `point` on the particle whose centroid is `centroid` (for B of a
  /// pair, pass minus the force the contact law returned for A).
  void addContact(const Vec3& f, const Vec3& point, const Vec3& centroid) {
    force += f;
    torque += (point - centroid).cross(f);
    norm_sum += manhattan(f);
  }
  /// The resultant `f` and its moment `torque` about the centroid of one pair's forces (the
  /// sub-contacts of a face contact): one contact force for the force ratio, as a pair counts
  /// once whatever model splits it.
  void addPair(const Vec3& f, const Vec3& moment) {
    force += f;
    torque += moment;
    norm_sum += manhattan(f);
  }
  /// A force acting at the centroid (gravity m g).
  void addBodyForce(const Vec3& f) {
    force += f;
    norm_sum += manhattan(f);
  }
  void clear() { *this = ForceAccumulator{}; }
};

/// The average force ratio of Keissar eq. 3.2:
///   R = sum_j <sum_i f_ij> / sum_j sum_i <f_ij>,
/// j over the free particles, i over every force on particle j (contact forces and gravity; the
/// local damping correction is numerical, not a force on the particle, and is left out). Each rank
/// adds its owned free particles (not ghosts, not fixed or driven ones); allreduce() then sums
/// numerator and denominator exactly (ExactSum), so R does not depend on the rank count.
class ForceRatio {
 public:
  /// One particle: its net force and the sum of the Manhattan norms of the forces making it up.
  void add(const Vec3& net_force, double norm_sum) {
    unbalanced_.add(manhattan(net_force));
    applied_.add(norm_sum);
  }
  void add(const ForceAccumulator& f) { add(f.force, f.norm_sum); }

  /// Sums over all ranks of `comm` (collective).
  void allreduce(MPI_Comm comm) {
    unbalanced_.allreduce(comm);
    applied_.allreduce(comm);
  }

  double unbalanced() const { return unbalanced_.value(); }
  double applied() const { return applied_.value(); }
  /// R; 0 when no force acts at all (nothing is out of balance).
  double value() const;

  void clear() { *this = ForceRatio{}; }

 private:
  ExactSum unbalanced_, applied_;
};

}  // namespace polydem::dynamics
