#include "polydem/run/tracker.h"

#include <algorithm>
#include <cmath>

#include "polydem/core/error.h"
#include "polydem/core/mpi_env.h"
#include "polydem/core/strings.h"
#include "polydem/dynamics/monitors.h"
#include "polydem/sim/simulation.h"

namespace polydem::run {

namespace {

// A tracked state as doubles: position 3, orientation 4, velocity 3, angular velocity 3, kinetic
// energy, contacts. The layout of the gather buffer and of the saved initial states.
constexpr int kDoubles = 15;

TrackedState unpackState(const double* b) {
  TrackedState s;
  s.position = {b[0], b[1], b[2]};
  s.orientation = Quat(b[3], b[4], b[5], b[6]);
  s.velocity = {b[7], b[8], b[9]};
  s.angular_velocity = {b[10], b[11], b[12]};
  s.kinetic_energy = b[13];
  s.contacts = static_cast<int>(b[14]);
  return s;
}

}  // namespace

void Tracker::track(Uid uid) {
  if (std::find(uids_.begin(), uids_.end(), uid) == uids_.end()) uids_.push_back(uid);
}

int Tracker::slot(Uid uid) const {
  const auto it = std::find(uids_.begin(), uids_.end(), uid);
  return it == uids_.end() ? -1 : static_cast<int>(it - uids_.begin());
}

void Tracker::gather(const sim::Simulation& sim) {
  const std::size_t n = uids_.size();
  buffer_.assign(n * kDoubles, 0.0);
  sum_.assign(n * kDoubles, 0.0);
  const auto& storage = sim.particles();
  const bool root = mpi::rank(sim.comm()) == 0;
  std::vector<int> contacts(n, 0);
  for (const auto& r : sim.contacts().records()) {
    if (!r.touching) continue;
    for (Uid uid : {r.key.lo, r.key.hi}) {
      const int s = slot(uid);
      if (s >= 0) ++contacts[s];
    }
  }
  for (std::size_t k = 0; k < n; ++k) {
    const int i = storage.indexOf(uids_[k]);
    if (i < 0) continue;
    const auto& p = storage[i];
    if (p.isGlobal() && !root) continue;  // replicated: rank 0 reports it
    double* b = &buffer_[k * kDoubles];
    const Vec3 w = p.isFixed() ? Vec3::Zero()
                   : sim.massProperties(i).mass > 0
                       ? dynamics::angularVelocity(p.orientation, p.angular_momentum,
                                                   sim.massProperties(i).principal_inertia)
                       : Vec3::Zero();
    const double values[kDoubles] = {
        p.position.x(),
        p.position.y(),
        p.position.z(),
        p.orientation.w(),
        p.orientation.x(),
        p.orientation.y(),
        p.orientation.z(),
        p.velocity.x(),
        p.velocity.y(),
        p.velocity.z(),
        w.x(),
        w.y(),
        w.z(),
        p.isFree() ? dynamics::kineticEnergy(p, sim.massProperties(i)) : 0.0,
        0.0};
    std::copy(values, values + kDoubles, b);
  }
  // A pair between two ranks is held by both: count each particle's contacts on its owner only.
  for (std::size_t k = 0; k < n; ++k) {
    const int i = storage.indexOf(uids_[k]);
    if (i >= 0 && (!storage[i].isGlobal() || root)) buffer_[k * kDoubles + 14] = contacts[k];
  }
  MPI_Allreduce(buffer_.data(), sum_.data(), static_cast<int>(buffer_.size()), MPI_DOUBLE, MPI_SUM,
                sim.comm());
  states_.resize(n);
  for (std::size_t k = 0; k < n; ++k) states_[k] = unpackState(&sum_[k * kDoubles]);
  if (!have_initial_) {
    initial_ = states_;
    have_initial_ = true;
  }
}

std::vector<double> Tracker::initialState() const {
  std::vector<double> v;
  if (!have_initial_) return v;
  for (const TrackedState& s : initial_) {
    const Quat& q = s.orientation;
    for (double x : {s.position.x(), s.position.y(), s.position.z(), q.w(), q.x(), q.y(), q.z(),
                     s.velocity.x(), s.velocity.y(), s.velocity.z(), s.angular_velocity.x(),
                     s.angular_velocity.y(), s.angular_velocity.z(), s.kinetic_energy,
                     static_cast<double>(s.contacts)}) {
      v.push_back(x);
    }
  }
  return v;
}

void Tracker::restoreInitial(const std::vector<double>& values) {
  if (values.empty()) return;  // not gathered yet when the state was saved
  if (values.size() != uids_.size() * kDoubles) {
    throw Error(cat("tracker state of ", values.size() / kDoubles, " particles for ", uids_.size(),
                    " tracked ones"));
  }
  initial_.resize(uids_.size());
  for (std::size_t k = 0; k < uids_.size(); ++k) initial_[k] = unpackState(&values[k * kDoubles]);
  have_initial_ = true;
}

double rotationAngle(const Quat& from, const Quat& to) {
  const Quat d = to * from.conjugate();
  const double s = d.vec().norm();
  return 2.0 * std::atan2(s, std::abs(d.w()));
}

double twistAngle(const Quat& from, const Quat& to, const Vec3& axis) {
  const Quat d = to * from.conjugate();
  const double along = d.vec().dot(axis);
  return 2.0 * std::atan2(std::abs(along), std::abs(d.w()));
}

}  // namespace polydem::run
