// [[shape]], [[particle]] and [[particle_grid]]: shapes become the vertex lists of their convex
// hulls (geometry::shapes builds the named ones), particles get uids in file order.
#include <algorithm>
#include <map>
#include <unordered_map>

#include "polydem/core/error.h"
#include "polydem/core/logging.h"
#include "polydem/core/random.h"
#include "polydem/core/strings.h"
#include "polydem/geometry/convex_polyhedron.h"
#include "polydem/geometry/shapes.h"
#include "polydem/scene/scene_sections.h"

namespace polydem::scene::detail {

namespace {

namespace shapes = geometry::shapes;

const std::vector<std::string> kShapeTypes = {
    "box",  "vertices",   "prism",        "triangular_prism", "pyramid",         "tetrahedron",
    "cube", "octahedron", "dodecahedron", "icosahedron",      "hexagonal_prism", "random"};

std::vector<std::string_view> shapeKeys(const std::string& type) {
  std::vector<std::string_view> keys = {"name", "type", "rotation", "scale"};
  auto add = [&keys](std::initializer_list<std::string_view> more) {
    keys.insert(keys.end(), more.begin(), more.end());
  };
  if (type == "box") add({"size", "min", "max"});
  if (type == "vertices") add({"vertices"});
  if (type == "prism") add({"polygon", "height"});
  if (type == "triangular_prism") add({"length", "width", "height"});
  if (type == "pyramid") add({"base", "height", "apex"});
  if (type == "tetrahedron" || type == "cube" || type == "octahedron" || type == "dodecahedron" ||
      type == "icosahedron") {
    add({"edge"});
  }
  if (type == "hexagonal_prism") add({"radius", "length"});
  if (type == "random") add({"count", "radius", "seed"});
  return keys;
}

shapes::Platonic platonicOf(const std::string& type) {
  if (type == "tetrahedron") return shapes::Platonic::kTetrahedron;
  if (type == "cube") return shapes::Platonic::kCube;
  if (type == "octahedron") return shapes::Platonic::kOctahedron;
  if (type == "dodecahedron") return shapes::Platonic::kDodecahedron;
  return shapes::Platonic::kIcosahedron;
}

const toml::array& pointArray(const Section& s, std::string_view key) {
  if (!s.has(key)) s.missing(key);
  const toml::array* a = s.find(key)->as_array();
  if (!a) s.fail(key, "expected an array of points, got " + typeName(*s.find(key)));
  return *a;
}

std::vector<Vec3> readVertices(const Section& s) {
  std::vector<Vec3> points;
  const toml::array& a = pointArray(s, "vertices");
  for (std::size_t i = 0; i < a.size(); ++i) {
    points.push_back(toVec3(s.context(), a[i], element(s.where("vertices"), i), Quantity::kLength));
  }
  return points;
}

// The polygon in the z = -height/2 plane, extruded by height along z.
std::vector<Vec3> readPrism(const Section& s) {
  const double height = s.requiredNumber("height", Quantity::kLength, Range::kPositive);
  const toml::array& a = pointArray(s, "polygon");
  std::vector<Vec3> base;
  for (std::size_t i = 0; i < a.size(); ++i) {
    const std::string what = element(s.where("polygon"), i);
    const toml::array* xy = a[i].as_array();
    if (!xy || xy->size() != 2) {
      s.context().fail(lineOf(a[i]), what + ": expected a point [x, y], got " + typeName(a[i]));
    }
    base.emplace_back(toNumber(s.context(), (*xy)[0], what + "[0]", Quantity::kLength),
                      toNumber(s.context(), (*xy)[1], what + "[1]", Quantity::kLength),
                      -0.5 * height);
  }
  return shapes::prism(base, Vec3(0, 0, height));
}

// The vertices of a shape of a built-in type, before its rotation and scale. `centre` is set when
// the shape is to be moved so that its centroid is at the origin.
std::vector<Vec3> typeVertices(const Section& s, const std::string& type, bool& centre) {
  centre = false;
  const auto positive = [&s](std::string_view key) {
    return s.requiredNumber(key, Quantity::kLength, Range::kPositive);
  };
  if (type == "box") {
    const bool sized = s.has("size"), cornered = s.has("min") || s.has("max");
    if (sized == cornered) s.failHere("give either size = [x, y, z] or min and max");
    if (sized)
      return shapes::boxAround(Vec3::Zero(),
                               0.5 * *s.vec3("size", Quantity::kLength, Range::kPositive));
    if (!s.has("min")) s.missing("min");
    if (!s.has("max")) s.missing("max");
    const Vec3 lo = *s.vec3("min", Quantity::kLength), hi = *s.vec3("max", Quantity::kLength);
    if (!((hi - lo).array() > 0.0).all()) s.fail("max", "must exceed min in every coordinate");
    return shapes::box(lo, hi);
  }
  if (type == "vertices") return readVertices(s);
  if (type == "prism") {
    centre = true;  // the polygon's centroid moves to the axis
    return readPrism(s);
  }
  if (type == "triangular_prism") {
    // Ridge along x on top; the centroid of the triangular cross-section is a third of the height
    // above the base.
    const double length = positive("length"), width = positive("width");
    const double height = positive("height");
    const double ridge_z = 2.0 * height / 3.0;
    return shapes::ridgePrism(Vec3(-0.5 * length, 0, ridge_z), Vec3(0.5 * length, 0, ridge_z),
                              0.5 * width, height);
  }
  if (type == "pyramid") {
    // The centroid of a pyramid is a quarter of the height above its base.
    const double base = positive("base"), height = positive("height");
    const std::string apex = s.choice("apex", {"up", "down"}, "up");
    const bool up = apex == "up";
    return shapes::squarePyramid(Vec3(0, 0, (up ? 0.75 : -0.75) * height), base, height,
                                 up ? shapes::Apex::kUp : shapes::Apex::kDown);
  }
  if (type == "hexagonal_prism") {
    // geometry builds the axis along z; turn it to x with z -> x, x -> y, y -> z, which leaves
    // two side faces horizontal (a flat face down).
    std::vector<Vec3> v = shapes::hexagonalPrism(positive("radius"), positive("length"));
    for (Vec3& p : v) p = Vec3(p.z(), p.x(), p.y());
    return v;
  }
  if (type == "random") {
    centre = true;
    if (!s.has("count")) s.missing("count");
    const std::int64_t count = *s.integer("count");
    if (count < 4) s.fail("count", "must be >= 4 (a polyhedron has at least 4 corners)");
    if (count > shapes::kMaxRandomPoints) {
      s.fail("count", cat(count, " is above the limit of ", shapes::kMaxRandomPoints,
                          " points (every point is a corner of the hull, and every contact with "
                          "the shape tests its faces)"));
    }
    const double radius = positive("radius");
    const std::int64_t seed = s.integer("seed", 0, Range::kNonNegative);
    return shapes::randomConvex(static_cast<int>(count), static_cast<std::uint64_t>(seed),
                                Vec3::Constant(radius));
  }
  return shapes::platonic(platonicOf(type), positive("edge"));
}

setup::ShapeSpec readShape(const Section& s) {
  setup::ShapeSpec shape;
  shape.name = s.requiredString("name");
  shape.line = s.line();
  const std::string type = s.requiredString("type");
  if (std::find(kShapeTypes.begin(), kShapeTypes.end(), type) == kShapeTypes.end()) {
    s.fail("type", "'" + type + "' is not one of " + join(kShapeTypes, ", "));
  }
  s.allowOnly(shapeKeys(type));

  Vec3 scale = Vec3::Ones();
  if (const toml::node* n = s.find("scale")) {
    scale = n->is_array() ? toVec3(s.context(), *n, s.where("scale"), Quantity::kDimensionless,
                                   Range::kPositive)
                          : Vec3::Constant(toNumber(s.context(), *n, s.where("scale"),
                                                    Quantity::kDimensionless, Range::kPositive));
  }
  const Quat rotation = s.rotation("rotation").value_or(Quat::Identity());

  try {
    bool centre = false;
    std::vector<Vec3> points = typeVertices(s, type, centre);
    geometry::BuildReport report;
    geometry::ConvexPolyhedron hull = geometry::ConvexPolyhedron::fromPoints(points, &report);
    const std::size_t dropped = report.interior_points.size() + report.boundary_points.size();
    if (dropped > 0 && type == "prism") {
      s.fail("polygon", "the polygon is not convex, or has a corner on a straight side");
    }
    if (dropped > 0) {
      log::warning(s.context().file() + ":" + std::to_string(s.line()) + ": " + s.name() + ": " +
                   std::to_string(dropped) + " of the points are not corners of the convex hull " +
                   "and are left out");
    }
    Vec3 shift = centre ? hull.centroid() : Vec3::Zero();
    if (type == "prism") shift.z() = 0.0;  // symmetric in z by construction
    // Scale, then rotate, both about the origin (the centroid of a built-in shape).
    for (const Vec3& v : hull.vertices()) {
      shape.vertices.push_back(rotation * (scale.cwiseProduct(v - shift)));
    }
  } catch (const GeometryError& e) {
    s.failHere(std::string("invalid shape: ") + e.what());
  }
  return shape;
}

// Reads the particle-level keys shared by [[particle]] and [[particle_grid]].
struct Common {
  int shape = -1, material = -1;
  Quat rotation = Quat::Identity();
  Vec3 velocity = Vec3::Zero();
};

int reference(const Section& s, std::string_view key, int index, const std::string& table) {
  if (index < 0) {
    s.fail(key, "no " + table + " is named '" + *s.string(key) + "'");
  }
  return index;
}

Common readCommon(const Section& s, const setup::Setup& scene) {
  Common c;
  c.shape =
      reference(s, "shape", indexByName(scene.shapes, s.requiredString("shape")), "[[shape]]");
  c.material = reference(s, "material", indexByName(scene.materials, s.requiredString("material")),
                         "[[material]]");
  c.rotation = s.rotation("rotation").value_or(c.rotation);
  c.velocity = s.vec3("velocity", Quantity::kVelocity).value_or(c.velocity);
  return c;
}

class ParticleReader {
 public:
  explicit ParticleReader(setup::Setup& scene) : scene_(scene) {}

  void single(const Section& s) {
    s.allowOnly({"shape", "material", "label", "position", "rotation", "velocity",
                 "angular_velocity", "fixed", "driver"});
    const Common c = readCommon(s, scene_);
    setup::ParticleSpec p = make(c, s.line());
    p.label = s.string("label").value_or("");
    claimLabel(s, p.label, "label");
    p.position = s.vec3("position", Quantity::kLength).value_or(p.position);
    p.angular_velocity =
        s.vec3("angular_velocity", Quantity::kAngularVelocity).value_or(p.angular_velocity);
    p.fixed = s.boolean("fixed").value_or(false);
    if (const auto name = s.string("driver")) {
      p.driver = reference(s, "driver", indexByName(scene_.drivers, *name), "[[driver]]");
      if (p.fixed) s.fail("driver", "a particle is either fixed or driven, not both");
    }
    scene_.particles.push_back(p);
  }

  void grid(const Section& s) {
    s.allowOnly({"shape", "material", "label_prefix", "origin", "spacing", "count", "rotation",
                 "velocity", "jitter", "seed"});
    const Common c = readCommon(s, scene_);
    const std::string prefix = s.string("label_prefix").value_or("");
    const Vec3 origin = s.vec3("origin", Quantity::kLength).value_or(Vec3::Zero());
    if (!s.has("spacing")) s.missing("spacing");
    const toml::node& sp = *s.find("spacing");
    const Vec3 spacing =
        sp.is_array()
            ? toVec3(s.context(), sp, s.where("spacing"), Quantity::kLength, Range::kPositive)
            : Vec3::Constant(toNumber(s.context(), sp, s.where("spacing"), Quantity::kLength,
                                      Range::kPositive));
    if (!s.has("count")) s.missing("count");
    const std::array<std::int64_t, 3> n = *s.int3("count", Range::kPositive);
    if (static_cast<double>(n[0]) * static_cast<double>(n[1]) * static_cast<double>(n[2]) > 1e9) {
      s.fail("count", "more than 1e9 particles in one grid");
    }
    checkParticleMemory(s, "count",
                        scene_.particles.size() + static_cast<std::uint64_t>(n[0] * n[1] * n[2]));
    const double jitter = s.number("jitter", Quantity::kLength, 0.0, Range::kNonNegative);
    SplitMix64 random(static_cast<std::uint64_t>(s.integer("seed", 0, Range::kNonNegative)));
    // x fastest, then y, then z: uids follow this order.
    for (std::int64_t k = 0; k < n[2]; ++k) {
      for (std::int64_t j = 0; j < n[1]; ++j) {
        for (std::int64_t i = 0; i < n[0]; ++i) {
          setup::ParticleSpec p = make(c, s.line());
          p.position =
              origin + spacing.cwiseProduct(Vec3(static_cast<double>(i), static_cast<double>(j),
                                                 static_cast<double>(k)));
          if (jitter > 0.0) {
            for (int d = 0; d < 3; ++d) p.position[d] += jitter * (2.0 * random.uniform() - 1.0);
          }
          if (!prefix.empty()) {
            p.label = cat(prefix, "_", i, "_", j, "_", k);
            claimLabel(s, p.label, "label_prefix");
          }
          scene_.particles.push_back(std::move(p));
        }
      }
    }
  }

  setup::ParticleSpec make(const Common& c, int line) {
    setup::ParticleSpec p;
    p.uid = static_cast<Uid>(scene_.particles.size() + 1);
    p.shape = c.shape;
    p.material = c.material;
    p.orientation = c.rotation;
    p.velocity = c.velocity;
    p.line = line;
    return p;
  }

  // Every block a shape of its own (named "<rock mass>#<i>") and a particle at its place.
  void rockMass(const Section& s) {
    RockMassCut cut = readRockMass(s, scene_);
    for (const setup::RockMassInfo& other : scene_.rock_masses) {
      if (other.name == cut.info.name) {
        s.fail("name", cat("rock mass '", other.name, "' is already defined at line ", other.line));
      }
    }
    cut.info.first_uid = static_cast<Uid>(scene_.particles.size() + 1);
    cut.info.blocks = static_cast<int>(cut.mass.blocks.size());
    // Its planes join the scene's joint planes: the faces they made carry their index.
    const int first_plane = static_cast<int>(scene_.joint_planes.size());
    for (std::size_t k = 0; k < cut.mass.planes.size(); ++k) {
      scene_.joint_planes.push_back(
          {cat(cut.info.name, "/", cut.mass.plane_names[k]), cut.plane_joint[k]});
    }
    // The shapes so far by name, looked up once per block (not a search of every shape).
    std::unordered_map<std::string, int> shape_line;
    for (const setup::ShapeSpec& other : scene_.shapes) shape_line.emplace(other.name, other.line);
    // Room for every block at once, not doubled on the way (two lists as long as the blocks).
    scene_.shapes.reserve(scene_.shapes.size() + cut.mass.blocks.size());
    scene_.particles.reserve(scene_.particles.size() + cut.mass.blocks.size());
    for (std::size_t i = 0; i < cut.mass.blocks.size(); ++i) {
      geometry::RockBlock& block = cut.mass.blocks[i];
      setup::ShapeSpec shape;
      shape.name = cat(cut.info.name, "#", i);
      shape.line = s.line();
      if (const auto other = shape_line.find(shape.name); other != shape_line.end()) {
        s.fail("name", cat("its block shape '", shape.name, "' clashes with the [[shape]] at line ",
                           other->second));
      }
      shape.face_planes = blockFacePlanes(cut.mass, block, first_plane);
      shape.vertices = std::move(block.vertices);
      Common c;
      c.shape = static_cast<int>(scene_.shapes.size());
      c.material = block.fixed ? cut.fixed_material : cut.material;
      scene_.shapes.push_back(std::move(shape));
      setup::ParticleSpec p = make(c, s.line());
      p.fixed = block.fixed;
      p.label = cat(cut.info.label_prefix, "_", i);
      claimLabel(s, p.label, "label_prefix");
      scene_.particles.push_back(std::move(p));
    }
    scene_.rock_masses.push_back(std::move(cut.info));
  }

 private:
  void claimLabel(const Section& s, const std::string& label, std::string_view key) {
    if (label.empty()) return;
    const auto [it, fresh] = labels_.emplace(label, s.line());
    if (!fresh) {
      s.fail(key,
             "the label '" + label + "' is already used at line " + std::to_string(it->second));
    }
  }

  setup::Setup& scene_;
  std::map<std::string, int> labels_;  // label -> line of its particle
};

}  // namespace

void readShapes(const Context& ctx, const toml::table& root, setup::Setup& scene) {
  for (const Section& s : entries(ctx, root, "shape", "name")) {
    setup::ShapeSpec shape = readShape(s);
    if (const int other = indexByName(scene.shapes, shape.name); other >= 0) {
      s.fail("name", "shape '" + shape.name + "' is already defined at line " +
                         std::to_string(scene.shapes[other].line));
    }
    scene.shapes.push_back(std::move(shape));
  }
}

void readParticles(const Context& ctx, const toml::table& root, setup::Setup& scene) {
  // Uids follow the file order of [[particle]] and [[particle_grid]] entries taken together.
  const std::vector<Section> singles = entries(ctx, root, "particle", "label");
  const std::vector<Section> grids = entries(ctx, root, "particle_grid", "label_prefix");
  const std::vector<Section> masses = entries(ctx, root, "rock_mass", "name");
  enum class Kind { kSingle, kGrid, kRockMass };
  struct Entry {
    int line;
    Kind kind;
    const Section* section;
  };
  std::vector<Entry> order;
  for (const Section& s : singles) order.push_back({s.line(), Kind::kSingle, &s});
  for (const Section& s : grids) order.push_back({s.line(), Kind::kGrid, &s});
  for (const Section& s : masses) order.push_back({s.line(), Kind::kRockMass, &s});
  std::stable_sort(order.begin(), order.end(),
                   [](const Entry& a, const Entry& b) { return a.line < b.line; });
  ParticleReader reader(scene);
  for (const Entry& e : order) {
    if (e.kind == Kind::kSingle) reader.single(*e.section);
    if (e.kind == Kind::kGrid) reader.grid(*e.section);
    if (e.kind == Kind::kRockMass) reader.rockMass(*e.section);
  }
  if (scene.particles.empty()) {
    ctx.fail(0, "the scene has no [[particle]], [[particle_grid]] or [[rock_mass]]");
  }
}

}  // namespace polydem::scene::detail
