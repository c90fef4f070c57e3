// The run settings of a scene file: [scene], [simulation], [kernel_params], [[material]],
// [[interaction]], [[driver]], [domain], [equilibrium], [output], [checkpoint]. Shapes and
// particles are in scene_bodies.cpp, [[joint]] in scene_joints.cpp, [[check]] in scene_checks.cpp.
#include "polydem/scene/scene_reader.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>

#include "polydem/contact/contact.h"
#include "polydem/core/error.h"
#include "polydem/core/file_kind.h"
#include "polydem/core/memory.h"
#include "polydem/core/strings.h"
#include "polydem/particles/material.h"
#include "polydem/scene/scene_sections.h"
#include "polydem/setup/snapshot_fields.h"

namespace polydem::scene {

namespace {

using detail::Context;
using detail::Range;
using detail::Section;

std::optional<Section> tableSection(const Context& ctx, const toml::table& root,
                                    std::string_view key) {
  const toml::node* n = root.get(key);
  if (!n) return std::nullopt;
  const toml::table* t = n->as_table();
  if (!t) {
    ctx.fail(detail::lineOf(*n), "'" + std::string(key) + "' must be a table: write [" +
                                     std::string(key) + "], got " + detail::typeName(*n));
  }
  return Section(ctx, *t, cat("[", key, "]"));
}

void readSceneTable(const Context& ctx, const toml::table& root, setup::Setup& scene) {
  const std::optional<Section> s = tableSection(ctx, root, "scene");
  if (!s) ctx.fail(0, "missing the [scene] table (it needs at least id = \"...\")");
  s->allowOnly({"id", "title", "source", "description"});
  scene.id = s->requiredString("id");
  scene.title = s->string("title").value_or("");
  scene.source = s->string("source").value_or("");
  scene.description = s->string("description").value_or("");
}

void readSimulation(const Context& ctx, const toml::table& root, setup::Setup& scene) {
  const std::optional<Section> s = tableSection(ctx, root, "simulation");
  if (!s)
    ctx.fail(0, "missing the [simulation] table (it needs at least dt and end_time or steps)");
  s->allowOnly({"kernel", "broadphase", "contact_model", "contact_point", "dt", "end_time", "steps",
                "gravity", "contact_margin"});
  scene.kernel = s->choice("kernel", contact::kernelNames(), scene.kernel);
  scene.broadphase = s->choice("broadphase", {"multilevel", "nbs", "all-pairs"}, scene.broadphase);
  scene.contact_model = s->choice("contact_model", setup::kContactModels, scene.contact_model);
  scene.contact_point =
      s->choice("contact_point", {"kernel", "overlap-centroid"}, scene.contact_point);
  if (scene.contact_point != "kernel" && scene.contact_model != "point") {
    s->fail("contact_point", "moves the single contact point: it needs contact_model = \"point\"");
  }
  scene.dt = s->requiredNumber("dt", Quantity::kTime, Range::kPositive);
  if (const auto t = s->number("end_time", Quantity::kTime, Range::kPositive)) scene.end_time = *t;
  if (const auto n = s->integer("steps", Range::kPositive)) scene.steps = *n;
  if (!scene.end_time && !scene.steps) s->failHere("give end_time or steps (or both)");
  scene.gravity = s->vec3("gravity", Quantity::kAcceleration).value_or(scene.gravity);
  scene.contact_margin =
      s->number("contact_margin", Quantity::kDimensionless, 0.0, Range::kNonNegative);
}

void readKernelParams(const Context& ctx, const toml::table& root, setup::Setup& scene) {
  const std::optional<Section> s = tableSection(ctx, root, "kernel_params");
  if (!s) return;
  s->allowOnly({"lp_rounding", "separating_axes"});
  scene.kernel_params.separating_axes = s->boolean("separating_axes").value_or(true);
  // A fraction of the inradius: at 1 the core left inside the rounding would be a point.
  double& r = scene.kernel_params.lp_rounding;
  r = s->bounded("lp_rounding", Quantity::kDimensionless, r, 0.0, 1.0, false);
  if (!(r > 0.0)) s->fail("lp_rounding", "must be > 0");
}

// The contact keys shared by [[material]] and [[interaction]], with their ranges.
void readContactKeys(const Section& s, double& kn, double& ks, double& friction_angle,
                     double& cohesion, double& normal_damping, double& penalty, double& jkn,
                     double& jks) {
  kn = s.number("kn", Quantity::kStiffness, kn, Range::kNonNegative);
  ks = s.number("ks", Quantity::kStiffness, ks, Range::kNonNegative);
  friction_angle = s.bounded("friction_angle", Quantity::kAngle, friction_angle, 0.0, 90.0, false);
  cohesion = s.number("cohesion", Quantity::kForce, cohesion, Range::kNonNegative);
  normal_damping =
      s.number("normal_damping", Quantity::kDimensionless, normal_damping, Range::kNonNegative);
  penalty = s.number("penalty", Quantity::kPressure, penalty, Range::kNonNegative);
  jkn = s.number("jkn", Quantity::kJointStiffness, jkn, Range::kNonNegative);
  jks = s.number("jks", Quantity::kJointStiffness, jks, Range::kNonNegative);
  // A joint stiffness applies to face contacts only; edge and corner contacts have no area and
  // keep the per-pair springs, which must then be there too.
  if (jkn > 0.0 && !(kn > 0.0)) s.fail("jkn", "needs kn > 0 too: edge and corner contacts use kn");
  if (jks > 0.0 && !(ks > 0.0)) s.fail("jks", "needs ks > 0 too: edge and corner contacts use ks");
}

void readMaterials(const Context& ctx, const toml::table& root, setup::Setup& scene) {
  std::map<std::string, int> lines;
  for (const Section& s : detail::entries(ctx, root, "material", "name")) {
    s.allowOnly({"name", "density", "kn", "ks", "friction_angle", "cohesion", "normal_damping",
                 "local_damping", "penalty", "jkn", "jks"});
    particles::Material m;
    m.name = s.requiredString("name");
    if (const auto it = lines.find(m.name); it != lines.end()) {
      s.fail("name",
             "material '" + m.name + "' is already defined at line " + std::to_string(it->second));
    }
    lines[m.name] = s.line();
    m.density = s.requiredNumber("density", Quantity::kDensity, Range::kPositive);
    readContactKeys(s, m.kn, m.ks, m.friction_angle, m.cohesion, m.normal_damping, m.penalty, m.jkn,
                    m.jks);
    m.local_damping = s.bounded("local_damping", Quantity::kDimensionless, 0.0, 0.0, 1.0, false);
    // Which of the two a kernel needs is the simulation's business; a material with neither
    // cannot push back at all.
    if (!(m.kn > 0.0) && !(m.penalty > 0.0)) {
      s.failHere("needs kn > 0 (penalty kernels) or penalty > 0 (potential kernels)");
    }
    scene.materials.push_back(m);
  }
  if (scene.materials.empty()) ctx.fail(0, "no [[material]] is defined");
}

int materialReference(const Section& s, const toml::node& node, const std::string& what,
                      const setup::Setup& scene) {
  const auto* name = node.as_string();
  if (!name) {
    s.context().fail(detail::lineOf(node),
                     what + ": expected a material name, got " + detail::typeName(node));
  }
  const int index = detail::indexByName(scene.materials, name->get());
  if (index < 0) {
    s.context().fail(detail::lineOf(node),
                     what + ": no [[material]] is named '" + name->get() + "'");
  }
  return index;
}

void readInteractions(const Context& ctx, const toml::table& root, setup::Setup& scene) {
  // Keys not given keep the value the material table would use for this pair.
  particles::MaterialTable table;
  for (const auto& m : scene.materials) table.add(m);
  table.finalize();
  std::map<std::pair<int, int>, int> seen;  // pair -> line
  for (const Section& s : detail::entries(ctx, root, "interaction", "")) {
    s.allowOnly({"materials", "kn", "ks", "friction_angle", "cohesion", "normal_damping", "penalty",
                 "jkn", "jks"});
    if (!s.has("materials")) s.missing("materials");
    const toml::array* names = s.find("materials")->as_array();
    if (!names || names->size() != 2) {
      s.fail("materials", "expected two material names, as in [\"rock\", \"steel\"]");
    }
    setup::Setup::Interaction in;
    in.a = materialReference(s, (*names)[0], s.where("materials") + "[0]", scene);
    in.b = materialReference(s, (*names)[1], s.where("materials") + "[1]", scene);
    const std::pair key{std::min(in.a, in.b), std::max(in.a, in.b)};
    if (const auto it = seen.find(key); it != seen.end()) {
      s.fail("materials", "the pair is already given at line " + std::to_string(it->second));
    }
    seen[key] = s.line();
    in.properties = table.pair(in.a, in.b);
    auto& p = in.properties;
    readContactKeys(s, p.kn, p.ks, p.friction_angle, p.cohesion, p.normal_damping, p.penalty, p.jkn,
                    p.jks);
    scene.interactions.push_back(in);
  }
}

void readDrivers(const Context& ctx, const toml::table& root, setup::Setup& scene) {
  for (const Section& s : detail::entries(ctx, root, "driver", "name")) {
    s.allowOnly({"name", "velocity", "angular_velocity", "pivot", "oscillation", "frequency",
                 "phase", "start_time", "end_time"});
    dynamics::DriverSpec d;
    d.name = s.requiredString("name");
    if (const int other = detail::indexByName(scene.drivers, d.name); other >= 0) {
      s.fail("name", "driver '" + d.name + "' is already defined at line " +
                         std::to_string(scene.drivers[other].line));
    }
    d.velocity = s.vec3("velocity", Quantity::kVelocity).value_or(d.velocity);
    d.angular_velocity =
        s.vec3("angular_velocity", Quantity::kAngularVelocity).value_or(d.angular_velocity);
    d.pivot = s.vec3("pivot", Quantity::kLength).value_or(d.pivot);
    d.oscillation = s.vec3("oscillation", Quantity::kVelocity).value_or(d.oscillation);
    d.frequency = s.number("frequency", Quantity::kFrequency, 0.0, Range::kNonNegative);
    d.phase = s.number("phase", Quantity::kPhase, 0.0);
    d.start_time = s.number("start_time", Quantity::kTime, 0.0, Range::kNonNegative);
    d.end_time = s.number("end_time", Quantity::kTime, d.end_time);
    if (!(d.end_time > d.start_time)) s.fail("end_time", "must be later than start_time");
    if (!d.oscillation.isZero() && !(d.frequency > 0.0)) {
      s.fail("oscillation", "needs frequency > 0");
    }
    d.line = s.line();
    scene.drivers.push_back(d);
  }
}

void readDomain(const Context& ctx, const toml::table& root, setup::Setup& scene) {
  const std::optional<Section> s = tableSection(ctx, root, "domain");
  if (!s) return;
  s->allowOnly({"min", "max", "blocks", "periodic", "rebalance_every", "balancer",
                "overlap_exchange", "sort_every"});
  setup::DomainSpec& d = scene.domain;
  d.line = s->lineOf("blocks");
  d.min = s->vec3("min", Quantity::kLength);
  d.max = s->vec3("max", Quantity::kLength);
  if (d.min && d.max && !((*d.max - *d.min).array() > 0.0).all()) {
    s->fail("max", "must exceed min in every coordinate");
  }
  if (d.min && d.max && !(*d.max - *d.min).allFinite()) {
    s->fail("max", "the box from min to max is too large: its extent overflows");
  }
  if (const auto b = s->int3("blocks", Range::kPositive)) {
    // The block forest numbers blocks with an int; each block costs memory whether it holds
    // particles or not (kBytesPerBlock: measured 51 bytes on one rank, more with METIS).
    constexpr double kBytesPerBlock = 256.0;
    const double count =
        static_cast<double>((*b)[0]) * static_cast<double>((*b)[1]) * static_cast<double>((*b)[2]);
    if (count > std::numeric_limits<int>::max()) {
      s->fail("blocks",
              cat(count, " blocks exceed the limit of ", std::numeric_limits<int>::max()));
    }
    const double available = static_cast<double>(availableMemoryBytes());
    if (available > 0.0 && kBytesPerBlock * count > available) {
      s->fail("blocks", cat(count, " blocks need about ", formatBytes(kBytesPerBlock * count),
                            ", more than the ", formatBytes(available), " of memory available"));
    }
    d.blocks = {static_cast<int>((*b)[0]), static_cast<int>((*b)[1]), static_cast<int>((*b)[2])};
    if (d.min && d.max) {
      for (int a = 0; a < 3; ++a) {
        if (!std::isnormal(((*d.max)[a] - (*d.min)[a]) / (*d.blocks)[a])) {
          s->fail("blocks",
                  cat("make blocks of edge ", ((*d.max)[a] - (*d.min)[a]) / (*d.blocks)[a],
                      " m along ", "xyz"[a], ", below the smallest normal number"));
        }
      }
    }
  }
  d.periodic = s->bool3("periodic").value_or(d.periodic);
  if ((d.periodic[0] || d.periodic[1] || d.periodic[2]) && !(d.min && d.max)) {
    s->fail("periodic", "a periodic axis needs the domain's min and max");
  }
  d.rebalance_every = s->integer("rebalance_every", d.rebalance_every, Range::kNonNegative);
  d.balancer = s->choice("balancer", {"metis", "sfc", "cyclic"}, d.balancer);
  d.overlap_exchange = s->boolean("overlap_exchange").value_or(d.overlap_exchange);
  d.sort_every = s->integer("sort_every", d.sort_every, Range::kNonNegative);
}

void readEquilibrium(const Context& ctx, const toml::table& root, setup::Setup& scene) {
  const std::optional<Section> s = tableSection(ctx, root, "equilibrium");
  if (!s) return;
  s->allowOnly({"enabled", "local_damping", "friction_angle", "force_ratio", "max_steps",
                "reset_velocities"});
  setup::EquilibriumSpec& e = scene.equilibrium;
  e.enabled = s->boolean("enabled").value_or(true);
  e.local_damping =
      s->bounded("local_damping", Quantity::kDimensionless, e.local_damping, 0.0, 1.0, false);
  e.friction_angle =
      s->bounded("friction_angle", Quantity::kAngle, e.friction_angle, 0.0, 90.0, false);
  e.force_ratio =
      s->number("force_ratio", Quantity::kDimensionless, e.force_ratio, Range::kPositive);
  e.max_steps = s->integer("max_steps", e.max_steps, Range::kPositive);
  e.reset_velocities = s->boolean("reset_velocities").value_or(e.reset_velocities);
}

/// `[output] fields` or `contact_fields`: names from `known`, each once; an unknown or repeated
/// name is an error at its own line. Absent: `defaults`.
std::vector<std::string> snapshotFields(const Section& s, std::string_view key,
                                        const std::vector<setup::SnapshotField>& known,
                                        const std::vector<std::string>& defaults) {
  const auto names = s.strings(key);
  if (!names) return defaults;
  const toml::array& array = *s.find(key)->as_array();
  for (std::size_t i = 0; i < names->size(); ++i) {
    const std::string& name = (*names)[i];
    std::string problem = setup::unknownField(known, name);
    if (problem.empty() &&
        std::find(names->begin(), names->begin() + i, name) != names->begin() + i) {
      problem = "field '" + name + "' is listed twice";
    }
    if (!problem.empty()) {
      s.context().fail(detail::lineOf(array[i]), detail::element(s.where(key), i) + ": " + problem);
    }
  }
  return *names;
}

void readOutput(const Context& ctx, const toml::table& root, setup::Setup& scene) {
  const std::optional<Section> s = tableSection(ctx, root, "output");
  if (!s) return;
  s->allowOnly({"series_every", "snapshot_every", "progress_every", "monitor", "snapshot_format",
                "fields", "contact_fields", "picture"});
  setup::OutputSpec& o = scene.output;
  o.series_every = s->integer("series_every", o.series_every, Range::kPositive);
  o.snapshot_every = s->integer("snapshot_every", o.snapshot_every, Range::kNonNegative);
  o.progress_every = s->integer("progress_every", o.progress_every, Range::kNonNegative);
  o.monitor = s->strings("monitor").value_or(o.monitor);
  for (std::size_t i = 0; i < o.monitor.size(); ++i) {
    const std::string& label = o.monitor[i];
    const bool found = std::any_of(scene.particles.begin(), scene.particles.end(),
                                   [&](const setup::ParticleSpec& p) { return p.label == label; });
    if (!found) s->fail("monitor", "no particle is labelled '" + label + "'");
  }
  o.snapshot_format = s->choice("snapshot_format", {"xdmf", "vtk"}, o.snapshot_format);
  o.fields = snapshotFields(*s, "fields", setup::kParticleFields, setup::kDefaultParticleFields);
  o.contact_fields =
      snapshotFields(*s, "contact_fields", setup::kContactFields, setup::kDefaultContactFields);
  o.picture = s->boolean("picture").value_or(o.picture);
}

void readCheckpoint(const Context& ctx, const toml::table& root, setup::Setup& scene) {
  const std::optional<Section> s = tableSection(ctx, root, "checkpoint");
  if (!s) return;
  s->allowOnly({"every_steps", "every_seconds", "keep"});
  setup::CheckpointSpec& c = scene.checkpoint;
  c.every_steps = s->integer("every_steps", c.every_steps, Range::kNonNegative);
  c.every_seconds =
      s->number("every_seconds", Quantity::kTime, c.every_seconds, Range::kNonNegative);
  const std::int64_t keep = s->integer("keep", c.keep, Range::kPositive);
  if (keep > std::numeric_limits<int>::max()) s->fail("keep", "is too large");
  c.keep = static_cast<int>(keep);
}

}  // namespace

setup::Setup parseScene(std::string_view text, const std::string& name_for_messages) {
  const Context ctx(name_for_messages);
  toml::table root;
  try {
    root = toml::parse(text, name_for_messages);
  } catch (const toml::parse_error& e) {
    ctx.fail(static_cast<int>(e.source().begin.line), "TOML syntax error at column " +
                                                          std::to_string(e.source().begin.column) +
                                                          ": " + std::string(e.description()));
  }
  // A study's random inputs (scene_random.h): a run takes the file's own values.
  root.erase("random");
  root.erase("realizations");
  static const std::vector<std::string_view> kSections = {
      "scene",       "simulation", "kernel_params", "material",      "interaction", "joint",
      "shape",       "driver",     "particle",      "particle_grid", "rock_mass",   "domain",
      "equilibrium", "output",     "checkpoint",    "check",         "fos",         "water",
      "seismic",     "bolt",       "operator"};
  Section(ctx, root, "top level").allowOnly(kSections);
  setup::Setup scene;
  scene.file = name_for_messages;
  scene.text = std::string(text);
  // Sections that others refer to come first, whatever their order in the file.
  readSceneTable(ctx, root, scene);
  readSimulation(ctx, root, scene);
  readKernelParams(ctx, root, scene);
  readMaterials(ctx, root, scene);
  readInteractions(ctx, root, scene);
  detail::readJoints(ctx, root, scene);
  detail::readShapes(ctx, root, scene);
  readDrivers(ctx, root, scene);
  detail::readParticles(ctx, root, scene);
  readDomain(ctx, root, scene);
  readEquilibrium(ctx, root, scene);
  readOutput(ctx, root, scene);
  readCheckpoint(ctx, root, scene);
  detail::readChecks(ctx, root, scene);
  detail::readFos(ctx, root, scene);
  detail::readWater(ctx, root, scene);
  detail::readSeismic(ctx, root, scene);
  detail::readBolts(ctx, root, scene);
  detail::readOperators(ctx, root, scene);
  return scene;
}

std::string readSceneText(const std::string& path) {
  // A FIFO would block the open below forever, a directory "opens" and reads as nothing.
  if (const std::string problem = notARegularFile(path); !problem.empty()) {
    throw InputError(path, 0, "cannot open the scene file: " + problem);
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, 0, "cannot open the scene file");
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) throw InputError(path, 0, "cannot read the scene file");
  return text.str();
}

setup::Setup readScene(const std::string& path) {
  return parseScene(readSceneText(path), path);
}

}  // namespace polydem::scene
