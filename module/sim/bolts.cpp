// Bolt forces from the replicated state and the gathered poses of the bolted blocks (bolts.h).
#include "polydem/sim/bolts.h"

#include <algorithm>
#include <limits>

#include "polydem/core/error.h"
#include "polydem/core/logging.h"
#include "polydem/core/strings.h"

namespace polydem::sim {

namespace {

constexpr int kPoseDoubles = 8;  // uid, centroid (3), orientation (w, x, y, z)

}  // namespace

dynamics::BoltLaw boltLaw(const setup::BoltSpec& bolt) {
  dynamics::BoltLaw law;
  law.axial_stiffness = bolt.axial_stiffness;
  law.axial_yield = bolt.axial_yield;
  law.shear_stiffness = bolt.shear_stiffness;
  law.shear_yield = bolt.shear_yield;
  law.pretension = bolt.pretension;
  law.ultimate_elongation =
      bolt.ultimate_elongation.value_or(std::numeric_limits<double>::infinity());
  return law;
}

Bolts::Bolts(const setup::Setup& scene, const std::function<InitialBody(std::size_t)>& body) {
  for (std::size_t k = 0; k < scene.bolts.size(); ++k) {
    const auto& spec = scene.bolts[k];
    names_.push_back(spec.name);
    laws_.push_back(boltLaw(spec));
    std::int32_t index = 0;
    for (const BoltCrossing& c : boltCrossings(scene, spec, body)) {
      joints_.push_back({c, static_cast<std::int32_t>(k), ++index, 0, 0});
      bolted_.push_back(c.a);
      bolted_.push_back(c.b);
    }
  }
  std::sort(bolted_.begin(), bolted_.end());
  bolted_.erase(std::unique(bolted_.begin(), bolted_.end()), bolted_.end());
  const auto slot = [&](Uid uid) {
    return static_cast<std::int32_t>(std::lower_bound(bolted_.begin(), bolted_.end(), uid) -
                                     bolted_.begin());
  };
  for (auto& j : joints_) {
    j.pose_a = slot(j.crossing.a);
    j.pose_b = slot(j.crossing.b);
  }
  states_.resize(joints_.size());
  last_.resize(joints_.size());
  poses_.resize(bolted_.size());
}

bool Bolts::restore(std::vector<dynamics::BoltJointState> states) {
  if (states.size() != states_.size()) return false;
  states_ = std::move(states);
  return true;
}

// Replicated bodies (fixed, driven) are local on every rank; each free one is owned by one rank,
// which sends its pose to all. Every rank ends with the same poses, bit for bit.
void Bolts::gatherPoses(const particles::ParticleStorage& particles, MPI_Comm comm) const {
  send_.clear();
  std::vector<std::uint8_t> seen(bolted_.size(), 0);
  for (std::size_t k = 0; k < bolted_.size(); ++k) {
    const int i = particles.indexOf(bolted_[k]);
    if (i < 0 || static_cast<std::size_t>(i) >= particles.localCount()) continue;
    const auto& p = particles[static_cast<std::size_t>(i)];
    if (p.isGlobal()) {
      poses_[k] = {p.position, p.orientation};
      seen[k] = 1;
      continue;
    }
    const Quat& q = p.orientation;
    send_.insert(send_.end(), {static_cast<double>(p.uid), p.position.x(), p.position.y(),
                               p.position.z(), q.w(), q.x(), q.y(), q.z()});
  }
  int ranks = 1;
  MPI_Comm_size(comm, &ranks);
  const int mine = static_cast<int>(send_.size());
  std::vector<int> counts(static_cast<std::size_t>(ranks)), offsets(counts.size() + 1, 0);
  MPI_Allgather(&mine, 1, MPI_INT, counts.data(), 1, MPI_INT, comm);
  for (std::size_t r = 0; r < counts.size(); ++r) offsets[r + 1] = offsets[r] + counts[r];
  receive_.resize(static_cast<std::size_t>(offsets.back()));
  MPI_Allgatherv(send_.data(), mine, MPI_DOUBLE, receive_.data(), counts.data(), offsets.data(),
                 MPI_DOUBLE, comm);
  for (std::size_t at = 0; at + kPoseDoubles <= receive_.size(); at += kPoseDoubles) {
    const double* r = &receive_[at];
    const auto uid = static_cast<Uid>(r[0]);
    const auto k = static_cast<std::size_t>(std::lower_bound(bolted_.begin(), bolted_.end(), uid) -
                                            bolted_.begin());
    poses_[k] = {Vec3(r[1], r[2], r[3]), Quat(r[4], r[5], r[6], r[7])};
    seen[k] = 1;
  }
  for (std::size_t k = 0; k < bolted_.size(); ++k) {
    if (!seen[k]) {
      throw SimulationError(cat("bolted block ", bolted_[k], " is held by no rank"));
    }
  }
}

void Bolts::addForces(const particles::ParticleStorage& particles,
                      std::span<dynamics::ForceAccumulator> forces, double time, MPI_Comm comm) {
  if (joints_.empty()) return;
  gatherPoses(particles, comm);
  // Adds f at world point x on the block `uid` if this rank owns it (free blocks only).
  const auto apply = [&](Uid uid, const Vec3& f, const Vec3& x, const Vec3& centroid) {
    const int i = particles.indexOf(uid);
    if (i < 0 || static_cast<std::size_t>(i) >= forces.size()) return;
    if (!particles[static_cast<std::size_t>(i)].isFree()) return;
    forces[static_cast<std::size_t>(i)].addContact(f, x, centroid);
  };
  for (std::size_t j = 0; j < joints_.size(); ++j) {
    const Joint& joint = joints_[j];
    const BoltCrossing& c = joint.crossing;
    const Pose& a = poses_[static_cast<std::size_t>(joint.pose_a)];
    const Pose& b = poses_[static_cast<std::size_t>(joint.pose_b)];
    const Vec3 xa = a.centroid + a.orientation * c.anchor_a;
    const Vec3 xb = b.centroid + b.orientation * c.anchor_b;
    const Vec3 axis = a.orientation * c.axis_a;
    const auto& law = laws_[static_cast<std::size_t>(joint.bolt)];
    last_[j] = dynamics::boltJointForce(law, axis, xb - xa, states_[j]);
    if (last_[j].broke_now) {
      log::info(cat("bolt '", names_[static_cast<std::size_t>(joint.bolt)], "' broke at t = ", time,
                    " s at its joint ", joint.index, " (between blocks ", c.a, " and ", c.b,
                    ", at (", num(xa.x()), ", ", num(xa.y()), ", ", num(xa.z()), ") m)"));
    }
    if (states_[j].broken) continue;
    const Vec3 f = last_[j].onFirst(axis);
    apply(c.a, f, xa, a.centroid);
    apply(c.b, -f, xb, b.centroid);
  }
}

std::vector<BoltLine> Bolts::lines(const particles::ParticleStorage& particles,
                                   MPI_Comm comm) const {
  std::vector<BoltLine> out;
  if (joints_.empty()) return out;
  gatherPoses(particles, comm);
  for (std::size_t j = 0; j < joints_.size(); ++j) {
    const Joint& joint = joints_[j];
    const Pose& a = poses_[static_cast<std::size_t>(joint.pose_a)];
    const Pose& b = poses_[static_cast<std::size_t>(joint.pose_b)];
    BoltLine line;
    line.from = a.centroid + a.orientation * joint.crossing.middle_a;
    line.to = b.centroid + b.orientation * joint.crossing.middle_b;
    line.axial_force = states_[j].broken ? 0.0 : last_[j].axial;
    line.shear_force = states_[j].broken ? 0.0 : last_[j].shear.norm();
    line.bolt = joint.bolt;
    line.broken = states_[j].broken;
    out.push_back(line);
  }
  return out;
}

}  // namespace polydem::sim
