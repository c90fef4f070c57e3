// verifyCheckpoint and its text form.
#include <algorithm>
#include <cstring>
#include <limits>
#include <sstream>

#include "polydem/checkpoint/checkpoint.h"
#include "polydem/checkpoint/checkpoint_read_all.h"
#include "polydem/core/exact_sum.h"
#include "polydem/core/mpi_env.h"
#include "polydem/core/state_hash.h"
#include "polydem/core/strings.h"

namespace polydem::checkpoint {

namespace {

/// Kinetic energy of one free particle: translation plus rotation, 1/2 L . w with
/// w = R diag(1 / (density I_k)) R^T L (body-frame principal moments I_k per unit density).
double kineticEnergy(const particles::Particle& p, const sim::CheckpointShape& shape,
                     double density) {
  const double mass = density * shape.volume;
  const Mat3 r = p.orientation.toRotationMatrix();
  const Vec3 body_l = r.transpose() * p.angular_momentum;
  const Vec3 body_w = body_l.cwiseQuotient(density * shape.principal_moments);
  return 0.5 * mass * p.velocity.squaredNorm() + 0.5 * body_l.dot(body_w);
}

}  // namespace

CheckpointSummary verifyCheckpoint(const std::filesystem::path& path, MPI_Comm comm) {
  CheckpointSummary s;
  const sim::CheckpointData d = readCheckpointVerified(path, comm, {}, &s.datasets);
  s.file = path.string();
  s.format_version = d.format_version;
  s.digest = d.digest;
  s.code_version = d.code_version;
  s.scene_file = d.scene_file;
  s.scene_hash = d.scene_hash;
  s.step = d.step;
  s.time = d.time;
  s.dt = d.dt;
  s.stage = d.stage;
  s.equilibrium_steps = d.equilibrium_steps;
  s.equilibrium_reached = d.equilibrium_reached;
  s.shapes = static_cast<int>(d.shapes.size());
  s.materials = static_cast<int>(d.materials.size());
  s.writer_ranks = d.writer_ranks;
  s.domain_lo = d.domain.lo;
  s.domain_hi = d.domain.hi;

  // Every rank holds all replicated particles and its share of the free ones.
  std::int64_t replicated = 0, free = 0, touching = 0;
  ExactSum energy;
  Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  for (const auto& p : d.particles) {
    lo = lo.cwiseMin(p.position);
    hi = hi.cwiseMax(p.position);
    if (p.isGlobal()) {
      ++replicated;
    } else {
      ++free;
      energy.add(kineticEnergy(p, d.shapes[p.shape], d.materials[p.material].density));
    }
  }
  for (const auto& h : d.pair_histories) touching += h.touching != 0;
  s.replicated_particles = replicated;
  s.particles = replicated + mpi::allreduceSum(free, comm);
  s.pairs = mpi::allreduceSum(static_cast<std::int64_t>(d.pair_keys.size()), comm);
  s.touching_pairs = mpi::allreduceSum(touching, comm);
  energy.allreduce(comm);
  s.kinetic_energy = energy.value();
  MPI_Allreduce(MPI_IN_PLACE, lo.data(), 3, MPI_DOUBLE, MPI_MIN, comm);
  MPI_Allreduce(MPI_IN_PLACE, hi.data(), 3, MPI_DOUBLE, MPI_MAX, comm);
  if (s.particles > 0) {
    s.particles_lo = lo;
    s.particles_hi = hi;
  }
  return s;
}

std::string formatCheckpointSummary(const CheckpointSummary& s) {
  std::ostringstream out;
  out.precision(17);
  auto vec = [](const Vec3& v) { return cat("(", v.x(), ", ", v.y(), ", ", v.z(), ")"); };
  out << "file: " << s.file << "\n"
      << "format version: " << s.format_version << "\n"
      << "digest: "
      << (s.format_version >= kFirstDigestCheckpointVersion
              ? BitHasher::hex(s.digest) + " (whole file, verified)"
              : std::string("none (the format predates the whole-file digest; per-dataset "
                            "checksums verified)"))
      << "\n"
      << "written by: polydem " << s.code_version << " on " << s.writer_ranks << " ranks\n"
      << "scene: " << s.scene_file << " (hash " << BitHasher::hex(s.scene_hash) << ")\n"
      << "step: " << s.step << "\n"
      << "time: " << shortest(s.time) << " s\n"
      << "dt: " << shortest(s.dt) << " s\n"
      << "stage: " << sim::toString(s.stage) << " (equilibrium steps " << s.equilibrium_steps
      << (s.equilibrium_reached ? ", reached" : ", not reached") << ")\n"
      << "particles: " << s.particles << " (" << s.replicated_particles << " fixed or driven)\n"
      << "pair histories: " << s.pairs << " (" << s.touching_pairs << " touching)\n"
      << "shapes: " << s.shapes << ", materials: " << s.materials << "\n"
      << "domain: " << vec(s.domain_lo) << " - " << vec(s.domain_hi) << " m\n"
      << "particle centroids: " << vec(s.particles_lo) << " - " << vec(s.particles_hi) << " m\n"
      << "kinetic energy (free particles, velocities at t - dt/2): " << shortest(s.kinetic_energy)
      << " J\n"
      << "datasets (" << s.datasets.size() << ", checksums verified):\n";
  for (const auto& d : s.datasets) {
    std::vector<std::string> dims;
    for (auto x : d.dims) dims.push_back(cat(x));
    out << "  " << d.name << " [" << (dims.empty() ? "scalar" : join(dims, " x ")) << "] "
        << BitHasher::hex(d.checksum) << "\n";
  }
  return out.str();
}

}  // namespace polydem::checkpoint
