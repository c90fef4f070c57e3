// Building a Simulation from a Scene: tables, domain, particles, contact laws.
#include <algorithm>
#include <cmath>
#include <memory>
#include <set>

#include <memory>
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
#include "polydem/geometry/shape_sharing.h"
#include "polydem/sim/face_planes.h"
#include "polydem/sim/load_balancing.h"

#include "polydem/sim/simulation.h"
#include "polydem/sim/step/operators.h"

namespace polydem::sim {

Simulation::Simulation(const setup::Setup& scene, MPI_Comm comm, const HostOperators& host, Unbuilt)
    : state_(scene, comm), stages_(state_) {
  state_.force_operators = sceneOperators(state_.scene, host);
}

StepState::StepState(const setup::Setup& scene_in, MPI_Comm comm_in)
    : scene(scene_in),
      comm(comm_in),
      rank(mpi::rank(comm_in)),
      ranks(mpi::size(comm_in)),
      loop(comm_in),
      exchange(comm_in) {
  ground = groundMotion(scene);
}

Simulation::Simulation(const setup::Setup& scene, MPI_Comm comm, const HostOperators& host)
    : Simulation(scene, comm, host, Unbuilt{}) {
  buildTables();
  buildBolts();
  buildLaws();
  buildDomain();
  placeParticles();
  suggestTimeStep();
  stages_.registerSteps();
  refreshGhosts(state_);
  state_.balancer.sampleNext();
  stages_.startLeapfrog();
  rebalance();  // by the work of the contact phase at t = 0, which startLeapfrog computed
}

Simulation::Simulation(const setup::Setup& scene, const CheckpointData& checkpoint,
                       const std::string& file, MPI_Comm comm, const HostOperators& host)
    : Simulation(scene, checkpoint, *std::make_unique<SavedHistoryChunks>(checkpoint, comm), file,
                 comm, host) {}

Simulation::Simulation(const setup::Setup& scene, const CheckpointData& checkpoint,
                       HistoryChunks& histories, const std::string& file, MPI_Comm comm,
                       const HostOperators& host)
    : Simulation(scene, comm, host, Unbuilt{}) {
  const Restart restart(state_, checkpoint, file);
  buildTables();
  restart.checkTables();
  buildBolts();
  restart.restoreBolts();
  buildLaws();
  computeExtents();
  restore_routing_ = restart.restoreParticles(histories);
  suggestTimeStep();
  stages_.registerSteps();
  restart.restoreStage(stages_);
}

Simulation::~Simulation() = default;

void Simulation::buildTables() {
  // A stop signal ends a long build (a rock mass of many blocks) every 256 shapes.
  constexpr std::size_t kPollEvery = 256;
  geometry::PolyhedronPool pool;  // congruent blocks of a rock mass keep one polyhedron
  state_.shapes.reserve(state_.scene.shapes.size());  // exactly sized: one per block of a mass
  state_.shape_frames.reserve(state_.scene.shapes.size());
  for (const auto& spec : state_.scene.shapes) {
    if ((state_.shapes.size() + 1) % kPollEvery == 0) {
      throwIfInterrupted([&] {
        return cat("building the shapes' hulls (", state_.shapes.size(), " of ",
                   state_.scene.shapes.size(), ")");
      });
    }
    try {
      geometry::BuildReport report;
      const auto poly = geometry::ConvexPolyhedron::fromPoints(spec.vertices, &report);
      auto frame = geometry::toBodyFrame(poly, spec.name);
      frame.shape.face_plane =
          matchFacePlanes(frame.shape, frame.rotation, frame.centroid, spec.face_planes);
      frame.shape.polyhedron = pool.share(std::move(frame.shape.polyhedron));
      state_.shapes.push_back(std::move(frame.shape));
      state_.shape_frames.push_back({frame.rotation, frame.centroid});
    } catch (const GeometryError& e) {  // e.g. a shape scaled flat after the reader built it
      throw InputError(state_.scene.file, spec.line,
                       cat("[[shape]] '", spec.name, "': ", e.what()));
    }
  }
  for (const auto& m : state_.scene.materials) state_.materials.add(m);
  for (const auto& i : state_.scene.interactions)
    state_.materials.setInteraction(i.a, i.b, i.properties);
  state_.materials.finalize();
  state_.densities = state_.materials.densities();
  state_.kernel = contact::makeKernel(state_.scene.kernel, state_.scene.kernel_params);
  state_.balancer.setModel(loadModelFor(state_.scene.kernel));
  state_.broadphase = broadphase::makeBroadPhase(state_.scene.broadphase);
  releaseShapeSpecs();
}

// The shape table holds every shape now: nothing reads the vertex lists and face planes of the
// simulation's copy of the setup again (a restart builds its table from its own copy). Released,
// they are most of that copy for a cut rock mass (a shape of its own per block, on every rank).
// Names and lines stay for messages.
void Simulation::releaseShapeSpecs() {
  for (auto& spec : state_.scene.shapes) {
    spec.vertices = std::vector<Vec3>();  // a new empty vector: clear() would keep the room
    spec.face_planes = std::vector<setup::FacePlane>();
  }
}

void Simulation::buildBolts() {
  if (state_.scene.bolts.empty()) return;
  state_.bolts = Bolts(state_.scene, [this](std::size_t i) {
    const auto& spec = state_.scene.particles[i];
    return InitialBody{&state_.shapes[static_cast<std::size_t>(spec.shape)], initialCentroid(spec),
                       initialOrientation(spec), !spec.fixed && spec.driver < 0};
  });
}

void Simulation::buildLaws() {
  // The setup's names are resolved once here, never per step.
  const auto model = dynamics::findContactModel(state_.scene.contact_model);
  if (!model) throw Error(setup::unknownContactModel(state_.scene.contact_model));
  state_.contact_model = *model;
  state_.overlap_centroid = state_.scene.contact_point == "overlap-centroid";
  const int n = static_cast<int>(state_.materials.size());
  const bool potential =
      state_.scene.kernel == "distance-potential" || state_.scene.kernel == "fdem";
  state_.law_main.resize(n * n);
  state_.law_equilibrium.resize(n * n);
  for (int a = 0; a < n; ++a) {
    for (int b = 0; b < n; ++b) {
      const auto& props = state_.materials.pair(a, b);
      const bool stiff = potential ? props.penalty > 0 : props.kn > 0;
      if (!stiff) {
        // Only an error if some particles of these materials can meet (checked lazily below).
        state_.law_main[a * n + b] = dynamics::lawCoefficients(props);
        state_.law_equilibrium[a * n + b] = state_.law_main[a * n + b];
        continue;
      }
      state_.law_main[a * n + b] = dynamics::lawCoefficients(props);
      state_.law_equilibrium[a * n + b] =
          dynamics::lawCoefficients(props, state_.scene.equilibrium.friction_angle);
    }
  }
  buildJointLaws();
  // Every material a particle uses must have the stiffness the kernel needs.
  for (const auto& p : state_.scene.particles) {
    const auto& m = state_.materials[p.material];
    const double k = potential ? m.penalty : m.kn;
    if (!(k > 0)) {
      throw InputError(state_.scene.file, p.line,
                       cat("material '", m.name, "' has no ", potential ? "penalty" : "kn",
                           ", which kernel '", state_.scene.kernel, "' needs"));
    }
  }
}

void Simulation::buildJointLaws() {
  state_.plane_joint.clear();
  state_.joint_law_main.clear();
  state_.joint_law_equilibrium.clear();
  // Only joints some plane uses matter; without any, the contact phase skips the lookup.
  bool used = false;
  for (const auto& p : state_.scene.joint_planes) used = used || p.joint >= 0;
  if (!used) return;
  for (const auto& p : state_.scene.joint_planes) state_.plane_joint.push_back(p.joint);
  const int n = static_cast<int>(state_.materials.size());
  for (const auto& j : state_.scene.joints) {
    try {
      for (int a = 0; a < n; ++a) {
        for (int b = 0; b < n; ++b) {
          state_.joint_law_main.push_back(
              dynamics::jointCoefficients(j.law, state_.law_main[a * n + b]));
          state_.joint_law_equilibrium.push_back(dynamics::jointCoefficients(
              j.law, state_.law_equilibrium[a * n + b], state_.scene.equilibrium.friction_angle));
        }
      }
    } catch (const Error& e) {
      throw InputError(state_.scene.file, j.line, cat("[[joint]] '", j.name, "': ", e.what()));
    }
  }
}

domain::Aabb Simulation::computeExtents() {
  // Particle extents: the domain defaults to their bounding box, grown by half its largest edge
  // on every side so that falling and sliding particles stay inside.
  Vec3 lo = Vec3::Constant(INFINITY), hi = Vec3::Constant(-INFINITY);
  double r_free = 0.0, r_all = 0.0;
  for (const auto& p : state_.scene.particles) {
    const auto& s = state_.shapes[p.shape];
    const Vec3 c = p.position + p.orientation * state_.shape_frames[p.shape].centroid;
    lo = lo.cwiseMin(c - Vec3::Constant(s.circumradius));
    hi = hi.cwiseMax(c + Vec3::Constant(s.circumradius));
    r_all = std::max(r_all, s.circumradius);
    if (!p.fixed && p.driver < 0) r_free = std::max(r_free, s.circumradius);
  }
  state_.margin = state_.scene.contact_margin * r_free;
  state_.r_free = r_free;
  // The broad phase and the ghost radius need a superset of the canonical-frame pair test.
  const double slack = 1e-9 * 2.0 * r_all;
  state_.ghost_range = r_free + state_.margin + slack;
  domain::Aabb box;
  if (state_.scene.domain.min && state_.scene.domain.max) {
    box = {*state_.scene.domain.min, *state_.scene.domain.max};
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
    if (state_.scene.domain.blocks) {
      counts = *state_.scene.domain.blocks;
    } else {
      // Blocks sized from where the free particles are; the fixed and driven bodies, which may
      // span the whole domain, play no part (domain/block_fit.h).
      std::vector<Vec3> centroids;
      for (const auto& p : state_.scene.particles) {
        if (p.fixed || p.driver >= 0) continue;
        const Vec3 c = p.position + p.orientation * state_.shape_frames[p.shape].centroid;
        if (box.contains(c)) centroids.push_back(c);  // outside: reported below
      }
      counts = fittedBlockCounts(state_, box, state_.scene.domain.periodic, centroids,
                                 /*collective=*/false);
    }
    state_.forest =
        std::make_unique<domain::BlockForest>(box, counts, state_.scene.domain.periodic);
  } catch (const domain::DomainError& e) {  // the same on every rank: all stop alike
    throw InputError(state_.scene.file, state_.scene.domain.line, cat("[domain]: ", e.what()));
  }
  // Every rank checks (so that all of them stop on an error); rank 0 alone counts the weights.
  std::vector<double> weights(state_.forest->numBlocks(), 0.0);
  for (const auto& p : state_.scene.particles) {
    if (p.fixed || p.driver >= 0) continue;
    const int b =
        state_.forest->blockOf(p.position + p.orientation * state_.shape_frames[p.shape].centroid);
    if (b < 0) {
      throw InputError(state_.scene.file, p.line,
                       cat("particle ", p.uid, (p.label.empty() ? "" : " '" + p.label + "'"),
                           " lies outside the [domain] box"));
    }
    if (state_.rank == 0) weights[b] += 1.0;
  }
  state_.forest->setRankMap(rankMap(state_, weights), state_.ranks);
}

void Simulation::placeParticles() {
  for (const auto& spec : state_.scene.particles) {
    // The spec places the shape's own frame; the body frame sits at the shape's centroid, turned
    // by its principal axes.
    const ShapeFrame& frame = state_.shape_frames[spec.shape];
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
      const double density = state_.densities[spec.material];
      p.angular_momentum =
          dynamics::angularMomentum(p.orientation, spec.angular_velocity,
                                    density * state_.shapes[spec.shape].principal_moments);
    }
    if (p.isGlobal() || state_.forest->ownerOf(p.position) == state_.rank)
      state_.storage.addLocal(p);
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
  for (const auto& spec : state_.scene.particles) {
    if (spec.fixed || spec.driver >= 0 || !seen.insert({spec.shape, spec.material}).second) {
      continue;
    }
    const auto& s = state_.shapes[spec.shape];
    const double density = state_.densities[spec.material];
    const double mass = density * s.volume;
    const Vec3 moments = density * s.principal_moments;
    const std::string what = cat("a particle of shape '", s.name, "' and material '",
                                 state_.materials[spec.material].name, "'");
    if (!std::isnormal(mass) || !std::isfinite(1.0 / mass)) {
      throw InputError(state_.scene.file, spec.line,
                       cat(what, " has mass ", mass, " kg (density ", density, " kg/m^3 x volume ",
                           s.volume, " m^3), not a usable number"));
    }
    const double largest = moments.maxCoeff(), smallest = moments.minCoeff();
    if (!std::isnormal(smallest) || !std::isfinite(largest) ||
        !(smallest >= kMinMomentRatio * largest)) {
      throw InputError(state_.scene.file, spec.line,
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
  for (const auto& spec : state_.scene.particles) {
    if (spec.fixed || spec.driver >= 0) continue;
    const auto& s = state_.shapes[spec.shape];
    const double density = state_.densities[spec.material];
    const auto& props = state_.materials.pair(spec.material, spec.material);
    // A joint stiffness per area meets its largest value on the particle's largest face.
    double largest_face = 0.0;
    for (const auto& f : s.polyhedron->faces()) largest_face = std::max(largest_face, f.area);
    const double k =
        std::max({props.kn, props.ks, props.jkn * largest_face, props.jks * largest_face});
    dt_particles.push_back({spec.uid, density * s.volume, density * s.principal_moments,
                            s.circumradius, k, props.normal_damping});
  }
  const auto suggestion = dynamics::suggestTimeStep(dt_particles);
  suggested_dt_ = suggestion.dt;
  const std::string warning = dynamics::timeStepWarning(state_.scene.dt, suggestion);
  if (!warning.empty()) log::warning(warning);
}

}  // namespace polydem::sim
