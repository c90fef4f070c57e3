#include "polydem/run/run_output.h"

#include <filesystem>

#include "polydem/core/error.h"
#include "polydem/core/mpi_env.h"
#include "polydem/dynamics/integrator.h"
#include "polydem/output/output_file.h"
#include "polydem/run/contact_sums.h"
#include "polydem/sim/water.h"

namespace polydem::run {

namespace {

std::vector<std::string> jointNames(const sim::Simulation& sim) {
  std::vector<std::string> names;
  for (const auto& j : sim.scene().joints) names.push_back(j.name);
  return names;
}

/// The [[joint]] whose plane made face `f` of `shape` (Setup::joints), -1: none.
std::int32_t faceJoint(const sim::Simulation& sim, const geometry::BodyShape& shape, int f) {
  const std::int32_t plane = shape.facePlane(f);
  return plane < 0 ? -1 : sim.scene().joint_planes[static_cast<std::size_t>(plane)].joint;
}

std::string sanitize(const std::string& name) {
  std::string out;
  for (char c : name) out += std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
  return out;
}

}  // namespace

RunOutput::RunOutput(const std::string& dir, sim::Simulation& sim, const Tracker& tracker,
                     const std::vector<std::pair<Uid, std::string>>& monitored,
                     const std::vector<std::unique_ptr<Check>>& checks, bool snapshots)
    : comm_(sim.comm()), monitored_(monitored) {
  (void)tracker;
  if (mpi::rank(sim.comm()) == 0) std::filesystem::create_directories(dir);
  MPI_Barrier(sim.comm());
  std::vector<std::string> columns = {"time", "step", "kinetic_energy", "force_ratio", "contacts"};
  for (const auto& [uid, label] : monitored_) {
    const std::string l = sanitize(label);
    for (const char* q : {"_x", "_y", "_z", "_vx", "_vy", "_vz", "_rotation"}) {
      columns.push_back(l + q);
    }
  }
  for (const auto& c : checks) {
    for (const auto& [name, value] : c->seriesColumns(sim)) columns.push_back(name);
  }
  series_ = std::make_unique<output::SeriesWriter>(dir + "/series.csv", columns, sim.comm());
  if (snapshots && sim.scene().output.snapshot_format == "vtk") {
    snapshots_ = std::make_unique<output::SnapshotWriter>(dir, sim.comm());
  } else if (snapshots) {
    xdmf_ = std::make_unique<output::XdmfSnapshotWriter>(
        dir, sim.comm(),
        output::XdmfSnapshotWriter::Options{sim.scene().output.fields,
                                            sim.scene().output.contact_fields, jointNames(sim)});
  }
  if (snapshots) bolts_ = std::make_unique<BoltOutput>(dir, sim);

  // Initial centroids of all free particles (indexed by uid) for the displacement field.
  struct Start {
    Uid uid;
    double x, y, z;
  };
  std::vector<Start> mine;
  const auto& storage = sim.particles();
  for (std::size_t i = 0; i < storage.localCount(); ++i) {
    const auto& p = storage[i];
    mine.push_back({p.uid, p.position.x(), p.position.y(), p.position.z()});
  }
  const auto all = mpi::allgatherv(mine, sim.comm());
  for (const auto& s : all) {
    if (s.uid >= initial_positions_.size()) initial_positions_.resize(s.uid + 1, Vec3::Zero());
    initial_positions_[s.uid] = {s.x, s.y, s.z};
  }
}

RunOutput::Written RunOutput::labelOf(const sim::Simulation& sim) {
  return {static_cast<int>(sim.stage()), sim.stepCount()};
}

void RunOutput::writeSeriesOnce(sim::Simulation& sim, const Tracker& tracker,
                                const std::vector<std::unique_ptr<Check>>& checks) {
  if (!(last_series_ == labelOf(sim))) writeSeries(sim, tracker, checks);
}

void RunOutput::writeSnapshotOnce(const sim::Simulation& sim) {
  if (!(last_snapshot_ == labelOf(sim))) writeSnapshot(sim);
}

void RunOutput::writeSeries(sim::Simulation& sim, const Tracker& tracker,
                            const std::vector<std::unique_ptr<Check>>& checks) {
  last_series_ = labelOf(sim);
  const auto m = sim.monitors();
  row_ = {sim.time(), static_cast<double>(sim.stepCount()), m.kinetic_energy, m.force_ratio,
          static_cast<double>(m.contacts)};
  for (const auto& [uid, label] : monitored_) {
    const auto& s = tracker.states()[tracker.slot(uid)];
    const auto& s0 = tracker.initial()[tracker.slot(uid)];
    row_.insert(row_.end(),
                {s.position.x(), s.position.y(), s.position.z(), s.velocity.x(), s.velocity.y(),
                 s.velocity.z(), rotationAngle(s0.orientation, s.orientation)});
  }
  for (const auto& c : checks) {
    for (const auto& [name, value] : c->seriesColumns(sim)) row_.push_back(value);
  }
  // Rank 0 writes (and may fail, on a full disk) alone; the others learn of it here, so that
  // every rank ends with the error instead of waiting in the next collective call.
  std::string error;
  try {
    series_->write(row_);
  } catch (const std::exception& e) {
    error = e.what();
  }
  output::throwIfAnyRankFailed(error, comm_);
}

// The water pressure on each face of particle i (sim/water.h), at the pose the snapshot shows and
// the time the water force of the step took; zeros without water and on fixed bodies.
void RunOutput::facePressures(const sim::Simulation& sim, std::size_t i, const Mat3& rotation,
                              std::vector<double>& out) {
  const auto& p = sim.particles()[i];
  const auto& shape = sim.shapes()[p.shape];
  const auto& faces = shape.polyhedron->faces();
  const auto& water = sim.scene().water;
  if (!water.enabled || !p.isFree()) {
    out.assign(faces.size(), 0.0);
    return;
  }
  normals_.clear();
  for (const auto& face : faces) normals_.push_back(rotation * face.normal);
  const double time = sim.stage() == sim::Stage::kEquilibrium ? 0.0 : sim.time();
  sim::faceWaterPressures(water, time, shape, vertices_, normals_, p.position, out);
}

void RunOutput::writeSnapshot(const sim::Simulation& sim) {
  if (!snapshots_ && !xdmf_) return;
  last_snapshot_ = labelOf(sim);
  const auto& storage = sim.particles();
  const bool root = mpi::rank(sim.comm()) == 0;
  sumContactsByParticle(sim, contact_count_, contact_force_);
  batch_.clear();
  for (std::size_t i = 0; i < storage.localCount(); ++i) {
    const auto& p = storage[i];
    if (p.isGlobal() && !root) continue;  // replicated bodies appear once
    const auto& body = sim.shapes()[p.shape];
    const auto& shape = *body.polyhedron;
    const Mat3 r = p.orientation.toRotationMatrix();
    vertices_.clear();
    for (const Vec3& v : shape.vertices()) vertices_.push_back(p.position + r * v);
    output::ParticleFields fields;
    fields.uid = p.uid;
    fields.velocity = p.velocity;
    fields.fixed = p.isFixed();
    fields.material = p.material;
    fields.position = p.position;
    fields.contact_count = contact_count_[i];
    fields.force = contact_force_[i];
    if (p.isFree()) {
      const auto mass = sim.massProperties(i);
      fields.angular_velocity =
          dynamics::angularVelocity(p.orientation, p.angular_momentum, mass.principal_inertia);
    }
    if (p.uid < initial_positions_.size()) {
      fields.displacement = p.position - initial_positions_[p.uid];
    }
    batch_.addParticle(fields, vertices_);
    facePressures(sim, i, r, pressures_);
    for (int f = 0; f < static_cast<int>(shape.faces().size()); ++f) {
      const auto k = static_cast<std::size_t>(f);
      batch_.addFace(shape.faces()[k].vertices, faceJoint(sim, body, f), pressures_[k]);
    }
  }
  contacts_.contacts.clear();
  for (const auto& r : sim.contacts().records()) {
    if (!r.touching || !r.a_is_local) continue;
    output::ContactRecord c;
    c.uid_a = r.key.lo;
    c.uid_b = r.key.hi;
    c.point = r.point;
    c.normal = r.normal;
    c.normal_force = r.normal_force;
    c.shear_force = r.force - r.force.dot(r.normal) * r.normal;
    c.joint = r.joint;
    contacts_.contacts.push_back(c);
  }
  if (snapshots_) snapshots_->write(sim.time(), sim.stepCount(), batch_, &contacts_);
  if (xdmf_) xdmf_->write(sim.time(), sim.stepCount(), batch_, &contacts_);
  if (bolts_) bolts_->write(sim);
}

void RunOutput::close() {
  std::string error;
  try {
    if (series_) series_->close();
  } catch (const std::exception& e) {
    error = e.what();
  }
  output::throwIfAnyRankFailed(error, comm_);
}

}  // namespace polydem::run
