// Building a Simulation from a Scene: tables, domain, particles, contact laws.
#include <algorithm>
#include <cmath>
#include <set>

#include "polydem/core/error.h"
#include "polydem/core/interrupt.h"
#include "polydem/core/logging.h"
#include "polydem/core/mpi_env.h"
#include "polydem/core/strings.h"
#include "polydem/domain/domain_error.h"
#include "polydem/domain/rebalance.h"
#include "polydem/dynamics/integrator.h"
#include "polydem/dynamics/time_step.h"
#include "polydem/geometry/body_shape.h"
#include "polydem/sim/face_planes.h"
#include "polydem/sim/simulation.h"

namespace polydem::sim {

Simulation::Simulation(const setup::Setup& scene, MPI_Comm comm, Unbuilt)
    : scene_(scene),
      comm_(comm),
      rank_(mpi::rank(comm)),
      ranks_(mpi::size(comm)),
      exchange_(comm),
      loop_(comm),
      parked_loop_(comm) {
  ground_ = groundMotion(scene_);
}

Simulation::Simulation(const setup::Setup& scene, MPI_Comm comm)
    : Simulation(scene, comm, Unbuilt{}) {
  buildTables();
  buildBolts();
  buildLaws();
  buildDomain();
  placeParticles();
  suggestTimeStep();
  registerSteps();
  refreshGhosts();
  sample_load_ = true;
  startLeapfrog();
  rebalance();  // by the work of the contact phase at t = 0, which startLeapfrog computed
}

Simulation::~Simulation() = default;

void Simulation::buildTables() {
  // A stop signal ends a long build (a rock mass of many blocks) every 256 shapes.
  constexpr std::size_t kPollEvery = 256;
  for (const auto& spec : scene_.shapes) {
    if ((shapes_.size() + 1) % kPollEvery == 0) {
      throwIfInterrupted([&] {
        return cat("building the shapes' hulls (", shapes_.size(), " of ", scene_.shapes.size(),
                   ")");
      });
    }
    try {
      geometry::BuildReport report;
      const auto poly = geometry::ConvexPolyhedron::fromPoints(spec.vertices, &report);
      auto frame = geometry::toBodyFrame(poly, spec.name);
      frame.shape.face_plane =
          matchFacePlanes(frame.shape, frame.rotation, frame.centroid, spec.face_planes);
      shapes_.push_back(std::move(frame.shape));
      shape_frames_.push_back({frame.rotation, frame.centroid});
    } catch (const GeometryError& e) {  // e.g. a shape scaled flat after the reader built it
      throw InputError(scene_.file, spec.line, cat("[[shape]] '", spec.name, "': ", e.what()));
    }
  }
  for (const auto& m : scene_.materials) materials_.add(m);
  for (const auto& i : scene_.interactions) materials_.setInteraction(i.a, i.b, i.properties);
  materials_.finalize();
  densities_ = materials_.densities();
  kernel_ = contact::makeKernel(scene_.kernel, scene_.kernel_params);
  load_model_ = loadModelFor(scene_.kernel);
  broadphase_ = broadphase::makeBroadPhase(scene_.broadphase);
}

void Simulation::buildBolts() {
  if (scene_.bolts.empty()) return;
  bolts_ = Bolts(scene_, [this](std::size_t i) {
    const auto& spec = scene_.particles[i];
    return InitialBody{&shapes_[static_cast<std::size_t>(spec.shape)], initialCentroid(spec),
                       initialOrientation(spec), !spec.fixed && spec.driver < 0};
  });
}

void Simulation::buildLaws() {
  // The setup's names are resolved once here, never per step.
  const auto model = dynamics::findContactModel(scene_.contact_model);
  if (!model) throw Error(setup::unknownContactModel(scene_.contact_model));
  contact_model_ = *model;
  overlap_centroid_ = scene_.contact_point == "overlap-centroid";
  const int n = static_cast<int>(materials_.size());
  const bool potential = scene_.kernel == "distance-potential" || scene_.kernel == "fdem";
  law_main_.resize(n * n);
  law_equilibrium_.resize(n * n);
  for (int a = 0; a < n; ++a) {
    for (int b = 0; b < n; ++b) {
      const auto& props = materials_.pair(a, b);
      const bool stiff = potential ? props.penalty > 0 : props.kn > 0;
      if (!stiff) {
        // Only an error if some particles of these materials can meet (checked lazily below).
        law_main_[a * n + b] = dynamics::lawCoefficients(props);
        law_equilibrium_[a * n + b] = law_main_[a * n + b];
        continue;
      }
      law_main_[a * n + b] = dynamics::lawCoefficients(props);
      law_equilibrium_[a * n + b] =
          dynamics::lawCoefficients(props, scene_.equilibrium.friction_angle);
    }
  }
  buildJointLaws();
  // Every material a particle uses must have the stiffness the kernel needs.
  for (const auto& p : scene_.particles) {
    const auto& m = materials_[p.material];
    const double k = potential ? m.penalty : m.kn;
    if (!(k > 0)) {
      throw InputError(scene_.file, p.line,
                       cat("material '", m.name, "' has no ", potential ? "penalty" : "kn",
                           ", which kernel '", scene_.kernel, "' needs"));
    }
  }
}

void Simulation::buildJointLaws() {
  plane_joint_.clear();
  joint_law_main_.clear();
  joint_law_equilibrium_.clear();
  // Only joints some plane uses matter; without any, the contact phase skips the lookup.
  bool used = false;
  for (const auto& p : scene_.joint_planes) used = used || p.joint >= 0;
  if (!used) return;
  for (const auto& p : scene_.joint_planes) plane_joint_.push_back(p.joint);
  const int n = static_cast<int>(materials_.size());
  for (const auto& j : scene_.joints) {
    try {
      for (int a = 0; a < n; ++a) {
        for (int b = 0; b < n; ++b) {
          joint_law_main_.push_back(dynamics::jointCoefficients(j.law, law_main_[a * n + b]));
          joint_law_equilibrium_.push_back(dynamics::jointCoefficients(
              j.law, law_equilibrium_[a * n + b], scene_.equilibrium.friction_angle));
        }
      }
    } catch (const Error& e) {
      throw InputError(scene_.file, j.line, cat("[[joint]] '", j.name, "': ", e.what()));
    }
  }
}

domain::Aabb Simulation::computeExtents() {
  // Particle extents: the domain defaults to their bounding box, grown by half its largest edge
  // on every side so that falling and sliding particles stay inside.
  Vec3 lo = Vec3::Constant(INFINITY), hi = Vec3::Constant(-INFINITY);
  double r_free = 0.0, r_all = 0.0;
  for (const auto& p : scene_.particles) {
    const auto& s = shapes_[p.shape];
    const Vec3 c = p.position + p.orientation * shape_frames_[p.shape].centroid;
    lo = lo.cwiseMin(c - Vec3::Constant(s.circumradius));
    hi = hi.cwiseMax(c + Vec3::Constant(s.circumradius));
    r_all = std::max(r_all, s.circumradius);
    if (!p.fixed && p.driver < 0) r_free = std::max(r_free, s.circumradius);
  }
  margin_ = scene_.contact_margin * r_free;
  r_free_ = r_free;
  // The broad phase and the ghost radius need a superset of the canonical-frame pair test.
  const double slack = 1e-9 * 2.0 * r_all;
  ghost_range_ = r_free + margin_ + slack;
  domain::Aabb box;
  if (scene_.domain.min && scene_.domain.max) {
    box = {*scene_.domain.min, *scene_.domain.max};
  } else {
    const double grow = 0.5 * (hi - lo).maxCoeff();
    box = {lo - Vec3::Constant(grow), hi + Vec3::Constant(grow)};
  }
  return box;
}

void Simulation::buildDomain() {
  const domain::Aabb box = computeExtents();
  try {
    domain::Index3 counts;
    if (scene_.domain.blocks) {
      counts = *scene_.domain.blocks;
    } else {
      // Blocks sized from where the free particles are; the fixed and driven bodies, which may
      // span the whole domain, play no part (domain/block_fit.h).
      std::vector<Vec3> centroids;
      for (const auto& p : scene_.particles) {
        if (p.fixed || p.driver >= 0) continue;
        const Vec3 c = p.position + p.orientation * shape_frames_[p.shape].centroid;
        if (box.contains(c)) centroids.push_back(c);  // outside: reported below
      }
      counts = fittedBlockCounts(box, scene_.domain.periodic, centroids, /*collective=*/false);
    }
    forest_ = std::make_unique<domain::BlockForest>(box, counts, scene_.domain.periodic);
  } catch (const domain::DomainError& e) {  // the same on every rank: all stop alike
    throw InputError(scene_.file, scene_.domain.line, cat("[domain]: ", e.what()));
  }
  // Every rank checks (so that all of them stop on an error); rank 0 alone counts the weights.
  std::vector<double> weights(forest_->numBlocks(), 0.0);
  for (const auto& p : scene_.particles) {
    if (p.fixed || p.driver >= 0) continue;
    const int b = forest_->blockOf(p.position + p.orientation * shape_frames_[p.shape].centroid);
    if (b < 0) {
      throw InputError(scene_.file, p.line,
                       cat("particle ", p.uid, (p.label.empty() ? "" : " '" + p.label + "'"),
                           " lies outside the [domain] box"));
    }
    if (rank_ == 0) weights[b] += 1.0;
  }
  forest_->setRankMap(rankMap(weights), ranks_);
}

void Simulation::placeParticles() {
  for (const auto& spec : scene_.particles) {
    // The spec places the shape's own frame; the body frame sits at the shape's centroid, turned
    // by its principal axes.
    const ShapeFrame& frame = shape_frames_[spec.shape];
    particles::Particle p;
    p.uid = spec.uid;
    p.shape = spec.shape;
    p.material = spec.material;
    p.flags = spec.fixed ? particles::kFixed : (spec.driver >= 0 ? particles::kDriven : 0u);
    p.driver = spec.driver;
    p.position = spec.position + spec.orientation * frame.centroid;
    p.orientation = (spec.orientation * frame.rotation).normalized();
    p.velocity = spec.fixed ? Vec3::Zero() : spec.velocity;
    if (p.isFree()) {
      const double density = densities_[spec.material];
      p.angular_momentum = dynamics::angularMomentum(
          p.orientation, spec.angular_velocity, density * shapes_[spec.shape].principal_moments);
    }
    if (p.isGlobal() || forest_->ownerOf(p.position) == rank_) storage_.addLocal(p);
  }
}

namespace {

/// Below this ratio of the smallest to the largest principal moment the smallest one is decided
/// by rounding (the moments are exact sums of terms of the size of the largest, about 1e-16 of
/// it each): a needle thinner than about 4e-6 of its length.
constexpr double kMinMomentRatio = 1e-10;

}  // namespace

// A free particle's mass and moments must be usable numbers: a subnormal or zero mass (a tiny
// density times a tiny volume) turns into infinite accelerations, a sliver's smallest moment into
// noise of either sign. Refused at the particle's line, once per shape and material.
void Simulation::checkFreeBodies() const {
  std::set<std::pair<int, int>> seen;
  for (const auto& spec : scene_.particles) {
    if (spec.fixed || spec.driver >= 0 || !seen.insert({spec.shape, spec.material}).second) {
      continue;
    }
    const auto& s = shapes_[spec.shape];
    const double density = densities_[spec.material];
    const double mass = density * s.volume;
    const Vec3 moments = density * s.principal_moments;
    const std::string what = cat("a particle of shape '", s.name, "' and material '",
                                 materials_[spec.material].name, "'");
    if (!std::isnormal(mass) || !std::isfinite(1.0 / mass)) {
      throw InputError(scene_.file, spec.line,
                       cat(what, " has mass ", mass, " kg (density ", density, " kg/m^3 x volume ",
                           s.volume, " m^3), not a usable number"));
    }
    const double largest = moments.maxCoeff(), smallest = moments.minCoeff();
    if (!std::isnormal(smallest) || !std::isfinite(largest) ||
        !(smallest >= kMinMomentRatio * largest)) {
      throw InputError(scene_.file, spec.line,
                       cat(what, " has principal moments of inertia (", moments.x(), ", ",
                           moments.y(), ", ", moments.z(), ") kg m^2: shape '", s.name,
                           "' is too thin (a sliver or needle; the smallest moment must be at "
                           "least ",
                           kMinMomentRatio, " of the largest)"));
    }
  }
}

void Simulation::suggestTimeStep() {
  checkFreeBodies();
  std::vector<dynamics::TimeStepParticle> dt_particles;
  for (const auto& spec : scene_.particles) {
    if (spec.fixed || spec.driver >= 0) continue;
    const auto& s = shapes_[spec.shape];
    const double density = densities_[spec.material];
    const auto& props = materials_.pair(spec.material, spec.material);
    // A joint stiffness per area meets its largest value on the particle's largest face.
    double largest_face = 0.0;
    for (const auto& f : s.polyhedron.faces()) largest_face = std::max(largest_face, f.area);
    const double k =
        std::max({props.kn, props.ks, props.jkn * largest_face, props.jks * largest_face});
    dt_particles.push_back({spec.uid, density * s.volume, density * s.principal_moments,
                            s.circumradius, k, props.normal_damping});
  }
  const auto suggestion = dynamics::suggestTimeStep(dt_particles);
  suggested_dt_ = suggestion.dt;
  const std::string warning = dynamics::timeStepWarning(scene_.dt, suggestion);
  if (!warning.empty()) log::warning(warning);
}

}  // namespace polydem::sim
