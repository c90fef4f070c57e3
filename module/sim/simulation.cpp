// The steps of a Simulation and its two stages.
#include "polydem/sim/simulation.h"

#include <chrono>
#include <cmath>

#include "polydem/core/error.h"
#include "polydem/core/exact_sum.h"
#include "polydem/core/logging.h"
#include "polydem/core/memory.h"
#include "polydem/core/mpi_env.h"
#include "polydem/core/state_hash.h"
#include "polydem/core/strings.h"
#include "polydem/domain/partition.h"
#include "polydem/domain/rebalance.h"
#include "polydem/dynamics/driver.h"
#include "polydem/dynamics/integrator.h"
#include "polydem/sim/pair_memory.h"
#include "polydem/sim/seismic.h"
#include "polydem/sim/water.h"

namespace polydem::sim {

dynamics::MassProperties Simulation::massProperties(std::size_t i) const {
  const auto& p = storage_[i];
  const double density = densities_[p.material];
  const auto& s = shapes_[p.shape];
  return {density * s.volume, density * s.principal_moments};
}

void Simulation::registerSteps() {
  loop_.setTimeStep(scene_.dt);
  loop_.add("sort", [this] { sortParticles(); });  // storage order (no result changes)
  loop_.add("derived", [this] { updateDerived(); });
  loop_.add("broadphase", [this] { findCandidates(); });
  loop_.add("contacts", [this] { computeContacts(); });
  loop_.add("integrate", [this] { integrate(); });
  loop_.add("communicate", [this] { communicate(); });
  loop_.addObserver("observe", [this] { observe(); });  // after step and time count the step
  loop_.stopWhen("interruption requested", [this] { return step_hook_ && step_hook_(); });
  loop_.setMonitor([this] {
    const auto m = monitors();
    return timeloop::Monitor{m.contacts, m.kinetic_energy, m.force_ratio};
  });
}

void Simulation::updateDerived() {
  storage_.updateDerived(shapes_, densities_);
  // Driven bodies turn with their driver's angular velocity, at the same half step as the
  // free particles' velocities (frozen during the equilibrium stage).
  const double t_half = time() - 0.5 * dt();
  for (std::size_t i = 0; i < storage_.localCount(); ++i) {
    const auto& p = storage_[i];
    if (!p.isDriven()) continue;
    const Vec3 w = stage_ == Stage::kEquilibrium
                       ? Vec3::Zero()
                       : dynamics::driverState(scene_.drivers[p.driver], t_half).angular_velocity;
    storage_.setAngularVelocity(i, w);
  }
}

// The broad phase's input from the storage; returns the largest radius.
double Simulation::fillSphereSet() {
  const std::size_t n = storage_.size();
  centers_.resize(n);
  radii_.resize(n);
  uids_.resize(n);
  active_.resize(n);
  double r_max = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    const auto& p = storage_[i];
    centers_[i] = storage_.placedPosition(i);
    radii_[i] = shapes_[p.shape].circumradius;
    uids_[i] = p.uid;
    active_[i] = i < storage_.localCount() && p.isFree();
    r_max = std::max(r_max, radii_[i]);
  }
  return r_max;
}

// Particles sit in storage in creation and arrival order, and the broad phase's grids visit them
// in cell order: past the caches, every gather of a particle and every pair of the contact phase
// waits on memory. At the first step of this Simulation (and of a restart) and every sort_every
// steps, the local particles are put in the cell order of the grid of the smallest free particles
// (broadphase/cell_order.h; for one size, exactly the order the multilevel grid gathers them in).
// Ghosts keep their places. No result changes (contact_phase.h: uid order throughout).
void Simulation::sortParticles() {
  const std::int64_t every = scene_.domain.sort_every;
  if (every <= 0 || (sort_started_ && loop_.step() % every != 0)) return;
  sort_started_ = true;
  const double r_max = fillSphereSet();
  double r_min = r_max;
  bool any_free = false;
  for (std::size_t i = 0; i < storage_.localCount(); ++i) {
    if (!active_[i]) continue;
    any_free = true;
    r_min = std::min(r_min, radii_[i]);
  }
  if (!any_free) return;
  // The reach findCandidates() gives the grid of particles of this size (cell_factor 1).
  const double reach = 2.0 * r_min + margin_ + 1e-9 * 2.0 * r_max;
  storage_.permuteLocals(
      cell_order_.order({centers_, radii_, uids_, active_}, storage_.localCount(), reach));
  ++sorts_;
}

void Simulation::findCandidates() {
  findPairs(candidates_);
  // Before the contact phase allocates its records and histories for every pair.
  if (candidates_.size() * bytesPerCandidatePair() > (std::size_t{64} << 20)) {
    if (const auto problem = pairMemoryProblem(scene_, storage_, radii_, margin_, candidates_,
                                               loop_.step(), availableMemoryBytes())) {
      throw SimulationError(*problem);
    }
  }
}

void Simulation::findPairs(std::vector<broadphase::CandidatePair>& out) {
  const double r_max = fillSphereSet();
  // A superset of the contact phase's own test, which is made in each pair's canonical frame.
  const double margin = margin_ + 1e-9 * 2.0 * r_max;
  try {
    broadphase_->findPairs({centers_, radii_, uids_, active_}, margin, out);
  } catch (const std::bad_alloc&) {
    throw SimulationError(cat("step ", loop_.step(), ": the broad phase ran out of memory for ",
                              "its candidate pairs (", out.size(),
                              " so far): particles overlap massively, or the contact margin of ",
                              margin_, " m reaches across many of them; check the scene for ",
                              "particles placed on top of each other and its contact_margin"));
  }
}

ContactSetup Simulation::contactSetup() const {
  ContactSetup setup;
  setup.shapes = &shapes_;
  setup.kernel = kernel_.get();
  setup.law = stage_ == Stage::kEquilibrium ? &law_equilibrium_ : &law_main_;
  setup.materials = static_cast<int>(materials_.size());
  setup.plane_joint = &plane_joint_;
  setup.joint_law = stage_ == Stage::kEquilibrium ? &joint_law_equilibrium_ : &joint_law_main_;
  setup.drivers = &scene_.drivers;
  setup.model = contact_model_;
  setup.overlap_centroid = overlap_centroid_;
  setup.margin = margin_;
  setup.dt = dt();
  setup.time = stage_ == Stage::kEquilibrium ? 0.0 : time();
  return setup;
}

void Simulation::computeContacts() {
  contact_stats_ = contact_phase_.run(contactSetup(), storage_, candidates_, history_, forces_);
  // The work of this phase, and where it was if the decomposition is weighed after this step
  // (the records hold storage indices, valid only until the particles move).
  const auto every = scene_.domain.rebalance_every;
  if (sample_load_ || (every > 0 && (loop_.step() + 1) % every == 0)) {
    load_sample_ = sampleLoad(storage_, contact_phase_.records(), load_model_);
    last_work_ = load_sample_.work;
    sample_load_ = false;
  } else {
    last_work_ = stepWork(storage_, contact_phase_.records(), load_model_);
  }
  // Gravity, and the pseudo-static earthquake load when the scene has one (sim/seismic.h).
  const Vec3 body = bodyAcceleration(scene_);
  for (std::size_t i = 0; i < storage_.localCount(); ++i) {
    if (storage_[i].isFree()) forces_[i].addBodyForce(storage_.mass(i) * body);
  }
  if (scene_.water.enabled) {
    addWaterForces(scene_.water, stage_ == Stage::kEquilibrium ? 0.0 : time(), shapes_, storage_,
                   std::span<dynamics::ForceAccumulator>(forces_.data(), storage_.localCount()));
  }
  if (!bolts_.empty()) {
    bolts_.addForces(storage_,
                     std::span<dynamics::ForceAccumulator>(forces_.data(), storage_.localCount()),
                     stage_ == Stage::kEquilibrium ? 0.0 : time(), comm_);
  }
  applyForceOperators();
  ratio_local_.clear();
  for (std::size_t i = 0; i < storage_.localCount(); ++i) {
    if (storage_[i].isFree()) ratio_local_.add(forces_[i]);
  }
}

void Simulation::applyForceOperators() {
  if (force_operators_.empty()) return;
  ForceStep step;
  step.time = stage_ == Stage::kEquilibrium ? 0.0 : time();
  step.dt = dt();
  step.equilibrium = stage_ == Stage::kEquilibrium;
  step.particles = &storage_;
  step.forces = std::span<dynamics::ForceAccumulator>(forces_.data(), storage_.localCount());
  for (const auto& op : force_operators_) callForceOperator(op.name, op.apply, step);
}

void Simulation::callForceOperator(const std::string& name, const ForceOperator& op,
                                   const ForceStep& step) {
  running_operator_ = &name;
  try {
    op(step);
  } catch (...) {
    running_operator_ = nullptr;
    throw;
  }
  running_operator_ = nullptr;
}

void Simulation::requireBetweenSteps(std::string_view what) const {
  if (!running_operator_) return;
  throw Error(cat(what, " called from inside force operator '", *running_operator_,
                  "': the step that calls the operator is half done (forces summed, particles ",
                  "not moved); step, change or checkpoint the simulation between steps, after ",
                  "step() or run() has returned"));
}

void Simulation::addForceOperator(std::string name, ForceOperator op) {
  requireBetweenSteps("addForceOperator");
  if (name.empty()) throw Error("addForceOperator: a force operator needs a name");
  if (!op) throw Error(cat("addForceOperator: force operator '", name, "' is empty"));
  for (const auto& existing : force_operators_) {
    if (existing.name == name) {
      throw Error(cat("addForceOperator: a force operator named '", name, "' is already added"));
    }
  }
  if (leapfrog_fresh_) startLeapfrogWith(name, op);
  force_operators_.push_back({std::move(name), std::move(op)});
}

// The constructor started the leapfrog (velocities to t = -dt/2) with the forces it knew; an
// operator added before the first step gets its half kick too, as if it had been there (the
// start is linear in the forces). Its velocities are then those at -dt/2, not the scene's.
void Simulation::startLeapfrogWith(const std::string& name, const ForceOperator& op) {
  std::vector<dynamics::ForceAccumulator> extra(storage_.localCount());
  ForceStep step;
  step.time = 0.0;
  step.dt = dt();
  step.particles = &storage_;
  step.forces = extra;
  callForceOperator(name, op, step);
  for (std::size_t i = 0; i < storage_.localCount(); ++i) {
    auto& p = storage_[i];
    if (p.isFree()) {
      dynamics::startLeapfrog(p, massProperties(i), extra[i].force, extra[i].torque, dt());
    }
  }
  refreshGhosts();
}

std::vector<std::string> Simulation::forceOperatorNames() const {
  std::vector<std::string> names;
  for (const auto& op : force_operators_) names.push_back(op.name);
  return names;
}

void Simulation::integrate() {
  leapfrog_fresh_ = false;
  if (ground_ && stage_ == Stage::kMain) moveWithGround();
  for (std::size_t i = 0; i < storage_.localCount(); ++i) {
    auto& p = storage_[i];
    if (p.isFree()) {
      const double alpha = stage_ == Stage::kEquilibrium ? scene_.equilibrium.local_damping
                                                         : materials_[p.material].local_damping;
      dynamics::advanceFree(p, massProperties(i), forces_[i].force, forces_[i].torque, dt(), alpha);
    } else if (p.isDriven() && stage_ == Stage::kMain) {
      dynamics::advanceDriven(p, scene_.drivers[p.driver], time(), dt());
    }
  }
}

// The fixed particles move with the ground of the [seismic] record (sim/ground_motion.h): by its
// exact displacement over the step, with its velocity at the half step, every rank alike.
void Simulation::moveWithGround() {
  const Vec3 shift = ground_->displacement(time() + dt()) - ground_->displacement(time());
  const Vec3 velocity = ground_->velocity(time() + 0.5 * dt());
  for (std::size_t i = 0; i < storage_.localCount(); ++i) {
    auto& p = storage_[i];
    if (!p.isFixed()) continue;
    p.position += shift;
    p.velocity = velocity;
  }
}

// A particle whose state is no longer finite, or that left the domain, ends the run with the
// scene file and the particle's line in the message (the exchange below would stop it too, but
// knows nothing of the scene).
void Simulation::checkParticlesInside(std::int64_t step) const {
  const auto& box = forest_->domain();
  for (std::size_t i = 0; i < storage_.localCount(); ++i) {
    const auto& p = storage_[i];
    if (!p.isFree()) continue;
    const bool finite = p.position.allFinite() && p.velocity.allFinite() &&
                        p.angular_momentum.allFinite() && p.orientation.coeffs().allFinite();
    if (finite && forest_->blockOf(forest_->wrap(p.position)) >= 0) continue;
    const std::string where = p.uid >= 1 && p.uid <= scene_.particles.size()
                                  ? cat(scene_.file, ":", scene_.particles[p.uid - 1].line, ": ")
                                  : cat(scene_.file, ": ");
    if (!finite) {
      throw SimulationError(cat(where, "particle ", p.uid, " has a state that is no longer finite ",
                                "at step ", step, " (position (", p.position.transpose(),
                                "), velocity (", p.velocity.transpose(), ")): forces or ",
                                "velocities overflowed; check gravity, densities, stiffnesses and ",
                                "dt in the scene"));
    }
    throw SimulationError(cat(where, "particle ", p.uid, " left the domain at (", p.position.x(),
                              ", ", p.position.y(), ", ", p.position.z(), ") at step ", step,
                              "; the domain is [", box.lo.x(), ", ", box.hi.x(), "] x [",
                              box.lo.y(), ", ", box.hi.y(), "] x [", box.lo.z(), ", ", box.hi.z(),
                              "]: enlarge [domain] min/max in the scene"));
  }
}

void Simulation::communicate() {
  const std::int64_t next_step = loop_.step() + 1;
  checkParticlesInside(next_step);
  // A new decomposition is weighed before the particles move, so that one exchange takes them to
  // their new owners (and their ghosts to the new neighbours).
  if (scene_.domain.rebalance_every > 0 && next_step % scene_.domain.rebalance_every == 0) {
    balanceDecomposition();
  }
  // While the messages travel, the next step's pairs of two local particles (sim/contact_phase.h).
  const bool in_flight =
      exchange_.post(*forest_, storage_, history_, shapes_, ghost_range_, next_step);
  if (in_flight && scene_.domain.overlap_exchange) evaluateEarly();
  exchange_stats_ = exchange_.finish(*forest_, storage_, history_);
  migrated_histories_ += exchange_stats_.histories_received;
  exchange_totals_ += exchange_stats_;
  step_exchange_totals_ += exchange_stats_;
  ++exchanges_;
}

// The local particles here now are those of the next step minus the arrivals, at their next
// positions: their derived data, their pairs (no ghost yet, so every pair has two local members)
// and the contact phase's work on those pairs. The next step's contact phase takes the results
// unless the state changed in between (every change between steps refreshes the ghosts, and
// refreshGhosts() forgets them).
void Simulation::evaluateEarly() {
  const auto t0 = std::chrono::steady_clock::now();
  updateDerived();
  findPairs(early_candidates_);
  contact_phase_.runEarly(contactSetup(), storage_, early_candidates_, history_);
  early_seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

void Simulation::refreshGhosts() {
  contact_phase_.discardEarly();
  exchange_stats_ = exchange_.refreshGhosts(*forest_, storage_, shapes_, ghost_range_);
}

void Simulation::observe() {
  for (const auto& o : observers_) o();
}

void Simulation::startLeapfrog() {
  // Velocities of a scene are given at t = 0; the leapfrog keeps them at t - dt/2. The forces at
  // t = 0 are computed on a copy of the (empty) history and bolt state so that this start leaves
  // no trace.
  const particles::ContactHistory saved = history_;
  const auto saved_bolts = bolts_.states();
  updateDerived();
  findCandidates();
  computeContacts();
  history_ = saved;
  bolts_.restore(saved_bolts);
  for (std::size_t i = 0; i < storage_.localCount(); ++i) {
    auto& p = storage_[i];
    if (p.isFree()) {
      dynamics::startLeapfrog(p, massProperties(i), forces_[i].force, forces_[i].torque, dt());
    }
  }
  refreshGhosts();
  leapfrog_fresh_ = true;
}

void Simulation::step() {
  requireBetweenSteps("step");
  loop_.singleStep();
}

// The equilibrium stage runs in its own loop, with the same steps; the main stage's loop is parked
// meanwhile.
void Simulation::enterEquilibrium() {
  std::swap(parked_loop_, loop_);
  loop_ = timeloop::TimeLoop(comm_);
  registerSteps();
  loop_.stopWhenForceRatioBelow(scene_.equilibrium.force_ratio,
                                [this] { return monitors().force_ratio; });
  loop_.stopAtStep(scene_.equilibrium.max_steps);
  stage_ = Stage::kEquilibrium;
}

std::int64_t Simulation::runEquilibrium() {
  requireBetweenSteps("runEquilibrium");
  if (!scene_.equilibrium.enabled || equilibrium_done_) return equilibrium_steps_;
  if (stage_ != Stage::kEquilibrium) enterEquilibrium();
  log::info(cat("initial equilibrium: local damping ", scene_.equilibrium.local_damping,
                ", friction ", scene_.equilibrium.friction_angle, " deg, until R < ",
                scene_.equilibrium.force_ratio));
  const auto reason = loop_.run();
  equilibrium_steps_ = loop_.step();
  if (reason == timeloop::StopReason::kUserCondition) return equilibrium_steps_;  // interrupted
  equilibrium_reached_ = reason == timeloop::StopReason::kForceRatio;
  log::info(cat("initial equilibrium ", equilibrium_reached_ ? "reached" : "NOT reached", " after ",
                equilibrium_steps_, " steps (", loop_.stopMessage(), ")"));
  equilibrium_timing_ = loop_.timing();
  std::swap(parked_loop_, loop_);
  stage_ = Stage::kMain;
  equilibrium_done_ = true;
  if (scene_.equilibrium.reset_velocities) {
    for (std::size_t i = 0; i < storage_.localCount(); ++i) {
      auto& p = storage_[i];
      if (!p.isFree()) continue;
      p.velocity.setZero();
      p.angular_momentum.setZero();
    }
    refreshGhosts();
  }
  return equilibrium_steps_;
}

void requireStopCondition(const setup::Setup& scene) {
  // The scene reader requires one; a scene changed from Python may have neither, and the loop's
  // own stop condition (the step hook) would then never hold.
  if (!scene.end_time && !scene.steps) {
    throw Error(cat("scene ", scene.file, ": neither end_time nor steps is set: nothing would ",
                    "stop the run"));
  }
}

timeloop::StopReason Simulation::run() {
  requireBetweenSteps("run");
  requireStopCondition(scene_);
  if (scene_.end_time) loop_.stopAtTime(*scene_.end_time);
  if (scene_.steps) loop_.stopAtStep(*scene_.steps);
  return loop_.run();
}

GlobalMonitors Simulation::monitors() {
  ExactSum kinetic, speed;
  dynamics::ForceRatio ratio = ratio_local_;
  std::int64_t contacts = 0, free_particles = 0;
  double max_speed = 0.0;
  for (std::size_t i = 0; i < storage_.localCount(); ++i) {
    const auto& p = storage_[i];
    if (!p.isFree()) continue;
    ++free_particles;
    kinetic += dynamics::kineticEnergy(p, massProperties(i));
    const double v = p.velocity.norm();
    speed += v;
    max_speed = std::max(max_speed, v);
  }
  for (const auto& r : contact_phase_.records()) contacts += r.touching && r.a_is_local;
  kinetic.allreduce(comm_);
  speed.allreduce(comm_);
  ratio.allreduce(comm_);
  GlobalMonitors m;
  m.kinetic_energy = kinetic.value();
  m.force_ratio = ratio.value();
  m.contacts = mpi::allreduceSum(contacts, comm_);
  m.particles = mpi::allreduceSum(free_particles, comm_);
  m.max_speed = mpi::allreduceMax(max_speed, comm_);
  m.mean_speed = m.particles > 0 ? speed.value() / static_cast<double>(m.particles) : 0.0;
  return m;
}

comm::StateHash Simulation::stateHash() const {
  comm::StateHash h = comm::globalStateHash(storage_, history_, comm_);
  // The bolts' state, replicated on every rank, joins the combined hash; a scene without bolts
  // keeps its hash.
  if (!bolts_.empty()) {
    BitHasher bolts;
    bolts.add(h.combined);
    for (const auto& b : bolts_.states()) {
      bolts.add(b.axial_plastic);
      bolts.add(b.shear_plastic);
      bolts.add(std::uint64_t{b.broken});
    }
    h.combined = bolts.value();
  }
  return h;
}

}  // namespace polydem::sim
