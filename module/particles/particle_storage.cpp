#include "polydem/particles/particle_storage.h"

#include "polydem/core/memory.h"

#include "polydem/core/error.h"
#include "polydem/core/strings.h"

namespace polydem::particles {

int ParticleStorage::indexOf(Uid uid) const {
  const auto it = index_of_.find(uid);
  return it == index_of_.end() ? -1 : it->second;
}

int ParticleStorage::addLocal(const Particle& p) {
  if (ghostCount() != 0) throw Error("ParticleStorage::addLocal: drop ghosts first");
  if (p.isGhost()) throw Error("ParticleStorage::addLocal: particle is flagged as ghost");
  if (!index_of_.emplace(p.uid, static_cast<int>(state_.size())).second) {
    throw Error(cat("particle uid ", p.uid, " exists twice on this rank"));
  }
  state_.push_back(p);
  shift_.push_back(Vec3::Zero());
  local_count_ = state_.size();
  return static_cast<int>(state_.size() - 1);
}

void ParticleStorage::removeLocal(std::size_t i) {
  if (ghostCount() != 0) throw Error("ParticleStorage::removeLocal: drop ghosts first");
  index_of_.erase(state_[i].uid);
  if (i + 1 != state_.size()) {
    state_[i] = state_.back();
    index_of_[state_[i].uid] = static_cast<int>(i);
  }
  state_.pop_back();
  shift_.pop_back();
  local_count_ = state_.size();
}

int ParticleStorage::addGhost(Particle p, const Vec3& shift) {
  p.flags |= kGhost;
  state_.push_back(p);
  shift_.push_back(shift);
  return static_cast<int>(state_.size() - 1);
}

void ParticleStorage::dropGhosts() {
  state_.resize(local_count_);
  shift_.resize(local_count_);
}

void ParticleStorage::permuteLocals(std::span<const std::int32_t> order) {
  const std::size_t n = local_count_;
  if (order.size() != n) {
    throw Error(cat("ParticleStorage::permuteLocals: ", order.size(), " indices for ", n,
                    " local particles"));
  }
  placed_.assign(n, 0);
  permuted_.resize(n);
  for (std::size_t k = 0; k < n; ++k) {
    const auto from = static_cast<std::size_t>(order[k]);
    if (order[k] < 0 || from >= n || placed_[from]) {
      throw Error(cat("ParticleStorage::permuteLocals: index ", order[k], " at place ", k,
                      " is out of range or taken twice"));
    }
    placed_[from] = 1;
    permuted_[k] = state_[from];
  }
  // Local particles have no periodic shift (addLocal), so shift_ needs no permutation; every uid
  // is in index_of_ already, so assigning through find() allocates nothing.
  for (std::size_t k = 0; k < n; ++k) {
    state_[k] = permuted_[k];
    index_of_.find(state_[k].uid)->second = static_cast<int>(k);
  }
}

void ParticleStorage::updateDerived(const ShapeTable& shapes, std::span<const double> densities) {
  const std::size_t n = state_.size();
  rotation_.resize(n);
  angular_velocity_.resize(n);
  mass_.resize(n);
  vertex_begin_.resize(n + 1);
  face_begin_.resize(n + 1);
  std::size_t total = 0, total_faces = 0;
  for (std::size_t i = 0; i < n; ++i) {
    vertex_begin_[i] = total;
    face_begin_[i] = total_faces;
    total += shapes[state_[i].shape].polyhedron->vertices().size();
    total_faces += shapes[state_[i].shape].polyhedron->faces().size();
  }
  vertex_begin_[n] = total;
  face_begin_[n] = total_faces;
  world_vertices_.resize(total);
  world_face_normals_.resize(total_faces);
  for (std::size_t i = 0; i < n; ++i) {
    const Particle& p = state_[i];
    const geometry::BodyShape& shape = shapes[p.shape];
    const double density = densities[p.material];
    const Mat3 r = p.orientation.toRotationMatrix();
    rotation_[i] = r;
    mass_[i] = density * shape.volume;
    angular_velocity_[i] =
        p.isFixed() ? Vec3::Zero()
                    : angularVelocityOf(r, density * shape.principal_moments, p.angular_momentum);
    const auto& body = shape.polyhedron->vertices();
    Vec3* out = world_vertices_.data() + vertex_begin_[i];
    const Vec3 placed = p.position + shift_[i];
    for (std::size_t v = 0; v < body.size(); ++v) out[v] = placed + r * body[v];
    // The same product as contact::Body::faceNormal() computes on demand.
    const auto& faces = shape.polyhedron->faces();
    Vec3* normal = world_face_normals_.data() + face_begin_[i];
    for (std::size_t f = 0; f < faces.size(); ++f) normal[f] = r * faces[f].normal;
  }
}

std::uint64_t ParticleStorage::stateBytes() const {
  return capacityBytes(state_) + capacityBytes(index_of_) + capacityBytes(shift_) +
         capacityBytes(permuted_) + capacityBytes(placed_);
}

std::uint64_t ParticleStorage::derivedBytes() const {
  return capacityBytes(rotation_) + capacityBytes(angular_velocity_) + capacityBytes(mass_) +
         capacityBytes(world_vertices_) + capacityBytes(vertex_begin_) +
         capacityBytes(world_face_normals_) + capacityBytes(face_begin_);
}

}  // namespace polydem::particles
