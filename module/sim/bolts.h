// The [[bolt]]s of a run (docs/scene-format.md "Rock bolts"): their crossings (bolt_geometry.h),
// their law (dynamics/bolt_law.h) and their state at every joint they cross.
//
// Bolts are few, so their state is replicated: every step each rank sends the poses of the
// bolted free blocks it owns to all (one MPI_Allgatherv of 8 doubles per block), every rank then
// evaluates every bolt from the same poses in the same order and updates the same state, and
// each rank adds the forces on the blocks it owns. The result is the same bits on any number of
// ranks, with nothing to migrate; a checkpoint stores the state once.
#pragma once

#include <mpi.h>

#include <span>
#include <string>
#include <vector>

#include "polydem/dynamics/bolt_law.h"
#include "polydem/dynamics/monitors.h"
#include "polydem/particles/particle_storage.h"
#include "polydem/setup/setup.h"
#include "polydem/sim/bolt_geometry.h"

namespace polydem::sim {

/// One line of a snapshot: a bolt across one joint, from the middle of its piece in one block to
/// the middle of its piece in the next, with its axial force.
struct BoltLine {
  Vec3 from = Vec3::Zero(), to = Vec3::Zero();  // m, world frame
  double axial_force = 0.0;                     // N, tension positive
  double shear_force = 0.0;                     // N, magnitude
  std::int32_t bolt = 0;                        // index into Setup::bolts
  bool broken = false;
};

class Bolts {
 public:
  Bolts() = default;
  /// The crossings of every bolt of `scene` (throws InputError for a bolt that crosses no joint);
  /// `body(i)` gives scene particle i's initial pose and shape.
  Bolts(const setup::Setup& scene, const std::function<InitialBody(std::size_t)>& body);

  bool empty() const { return joints_.empty(); }
  /// The state at every joint of every bolt, bolts in file order, joints from each bolt's start:
  /// what a checkpoint stores.
  const std::vector<dynamics::BoltJointState>& states() const { return states_; }
  /// Replaces the state (a restart); false if `states` has not one entry per joint.
  bool restore(std::vector<dynamics::BoltJointState> states);
  std::size_t jointCount() const { return joints_.size(); }

  /// Adds the bolt forces to `forces` (parallel to this rank's local particles, [0,
  /// particles.localCount())) and updates the state. Collective. `time` is for the console line
  /// of a bolt that breaks.
  void addForces(const particles::ParticleStorage& particles,
                 std::span<dynamics::ForceAccumulator> forces, double time, MPI_Comm comm);
  /// The snapshot lines at the current poses, with the forces of the last addForces(). Collective.
  std::vector<BoltLine> lines(const particles::ParticleStorage& particles, MPI_Comm comm) const;

 private:
  struct Joint {
    BoltCrossing crossing;
    std::int32_t bolt = 0;
    std::int32_t index = 0;               // from the bolt's start, 1-based in messages
    std::int32_t pose_a = 0, pose_b = 0;  // into poses_ (bolted_ order)
  };
  struct Pose {
    Vec3 centroid = Vec3::Zero();
    Quat orientation = Quat::Identity();
  };
  /// The poses of every bolted block, in bolted_ order (collective).
  void gatherPoses(const particles::ParticleStorage& particles, MPI_Comm comm) const;

  std::vector<std::string> names_;
  std::vector<dynamics::BoltLaw> laws_;  // per bolt
  std::vector<Joint> joints_;
  std::vector<dynamics::BoltJointState> states_;  // per joint
  std::vector<dynamics::BoltJointForce> last_;    // per joint, of the last addForces()
  std::vector<Uid> bolted_;                       // every block a joint names, by uid
  mutable std::vector<Pose> poses_;
  mutable std::vector<double> send_, receive_;
};

/// The law of `bolt` (its yield forces as given; [fos] reduce_bolts divides them beforehand).
dynamics::BoltLaw boltLaw(const setup::BoltSpec& bolt);

}  // namespace polydem::sim
