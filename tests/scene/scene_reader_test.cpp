// The scene reader on valid input: a full scene lands field by field with units converted, shape
// types follow their documented layout, grids are seeded, and the example scene parses.
#include "polydem/scene/scene_reader.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>

#include "polydem/contact/contact.h"
#include "polydem/core/error.h"
#include "polydem/core/strings.h"
#include "polydem/geometry/convex_polyhedron.h"
#include "scene_test_support.h"

namespace polydem::scene {
namespace {

using namespace scene_test;

const std::string kFull = R"(# every key of the format
[scene]
id = "T-FULL"
title = "Every key"
source = "the test"
description = "round trip"

[simulation]
kernel = "fcp"
broadphase = "nbs"
contact_model = "point"
contact_point = "overlap-centroid"
dt = "50 us"
end_time = "2 s"
steps = 4e4
gravity = [0, "-1 m/s^2", -9.81]
contact_margin = 0.1

[kernel_params]
lp_rounding = 0.1
separating_axes = false

[domain]
min = [-1, -2, "-300 cm"]
max = [1, 2, 3]
blocks = [2, 1, 3]
periodic = [true, false, false]
rebalance_every = 500
balancer = "sfc"
overlap_exchange = true

[equilibrium]
local_damping = 0.7
friction_angle = "1.5 rad"
force_ratio = 1e-6
max_steps = 5000
reset_velocities = false

[[material]]
name = "rock"
density = "2.5 g/cm^3"
kn = "2 GN/m"
ks = "1e9 N/m"
friction_angle = "30 deg"
cohesion = "1 kN"
normal_damping = 0.2
local_damping = 0.05
penalty = "3 GPa"
jkn = "40 GPa/m"

[[material]]
name = "steel"
density = 7800
kn = 5e9
ks = 4e9
friction_angle = 20
penalty = 1e9

[[interaction]]
materials = ["steel", "rock"]
ks = "0.5 GN/m"
friction_angle = 10
jks = "2e10 Pa/m"

[[shape]]
name = "brick"
type = "box"
size = ["2 mm", "4 mm", "6 mm"]

[[shape]]
name = "slab"
type = "box"
min = [-1, -1, -1]
max = [1, 1, 0]

[[shape]]
name = "tet"
type = "vertices"
vertices = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]]

[[shape]]
name = "turned"
type = "box"
size = [2, 4, 6]
rotation = { axis = [0, 0, 1], angle = 90 }
scale = 0.5

[[driver]]
name = "shake"
velocity = [0.1, 0, 0]
angular_velocity = [0, 0, "180 deg/s"]
pivot = [0, 0, "1 mm"]
oscillation = [0, 0, 0.01]
frequency = "5 Hz"
phase = "90 deg"
start_time = "1 s"
end_time = 3

[[particle]]
label = "base"
shape = "slab"
material = "rock"
driver = "shake"

[[particle_grid]]
shape = "brick"
material = "steel"
label_prefix = "g"
origin = [0, 0, "10 mm"]
spacing = ["3 mm", "5 mm", "7 mm"]
count = [2, 3, 2]
rotation = { euler_zyx = [90, 0, 0] }
velocity = [0, 0, -1]

[[particle]]
label = "top"
shape = "tet"
material = "steel"
position = [0, 0, "1 m"]
rotation = [{ axis = [1, 0, 0], angle = 90 }, { quaternion = [0, 0, 0, 2] }]
velocity = ["1 mm/s", 0, 0]
angular_velocity = [0, 0.5, 0]
fixed = true

[output]
series_every = 5
snapshot_every = 100
progress_every = 1000
monitor = ["top", "g_1_2_1"]

[checkpoint]
every_steps = 1000
every_seconds = "2 min"
keep = 3

[[check]]
name = "drop"
kind = "displacement"
expected = "5 mm"
tolerance = 1e-4
compare = "rel"
reference = "eq. 1"
particle = "top"
direction = [0, 2, 0]
at = "end"

[[check]]
name = "info"
kind = "rotation"
particle = "top"
compare = "report"
tolerance = "1 deg"
)";

// Largest |coordinate| of the vertices, per axis.
Vec3 extent(const std::vector<Vec3>& v) {
  Vec3 e = Vec3::Zero();
  for (const Vec3& p : v) e = e.cwiseMax(p.cwiseAbs());
  return e;
}

std::set<std::array<double, 3>> asSet(const std::vector<Vec3>& v) {
  std::set<std::array<double, 3>> out;
  for (const Vec3& p : v) out.insert({p.x(), p.y(), p.z()});
  return out;
}

TEST(SceneReader, FullSceneLandsFieldByField) {
  const setup::Setup s = parseScene(kFull, "full.toml");
  EXPECT_EQ(s.file, "full.toml");
  EXPECT_EQ(s.id, "T-FULL");
  EXPECT_EQ(s.title, "Every key");
  EXPECT_EQ(s.source, "the test");
  EXPECT_EQ(s.description, "round trip");

  EXPECT_EQ(s.kernel, "fcp");
  EXPECT_EQ(s.broadphase, "nbs");
  EXPECT_EQ(s.contact_model, "point");
  EXPECT_EQ(s.contact_point, "overlap-centroid");
  EXPECT_EQ(s.dt, 50e-6);
  EXPECT_EQ(s.end_time, 2.0);
  EXPECT_EQ(s.steps, 40000);
  EXPECT_EQ(s.gravity, Vec3(0, -1, -9.81));
  EXPECT_EQ(s.contact_margin, 0.1);
  EXPECT_EQ(s.kernel_params.lp_rounding, 0.1);
  EXPECT_FALSE(s.kernel_params.separating_axes);

  ASSERT_TRUE(s.domain.min && s.domain.max && s.domain.blocks);
  EXPECT_EQ(*s.domain.min, Vec3(-1, -2, -3));
  EXPECT_EQ(*s.domain.max, Vec3(1, 2, 3));
  EXPECT_EQ(*s.domain.blocks, (std::array<int, 3>{2, 1, 3}));
  EXPECT_EQ(s.domain.periodic, (std::array<bool, 3>{true, false, false}));
  EXPECT_EQ(s.domain.rebalance_every, 500);
  EXPECT_EQ(s.domain.balancer, "sfc");
  EXPECT_TRUE(s.domain.overlap_exchange);

  EXPECT_TRUE(s.equilibrium.enabled);
  EXPECT_EQ(s.equilibrium.local_damping, 0.7);
  EXPECT_DOUBLE_EQ(s.equilibrium.friction_angle, radToDeg(1.5));
  EXPECT_EQ(s.equilibrium.force_ratio, 1e-6);
  EXPECT_EQ(s.equilibrium.max_steps, 5000);
  EXPECT_FALSE(s.equilibrium.reset_velocities);

  ASSERT_EQ(s.materials.size(), 2u);
  const particles::Material& rock = s.materials[0];
  EXPECT_EQ(rock.name, "rock");
  EXPECT_EQ(rock.density, 2500.0);
  EXPECT_EQ(rock.kn, 2e9);
  EXPECT_EQ(rock.ks, 1e9);
  EXPECT_EQ(rock.friction_angle, 30.0);  // degrees stay degrees
  EXPECT_EQ(rock.cohesion, 1000.0);
  EXPECT_EQ(rock.normal_damping, 0.2);
  EXPECT_EQ(rock.local_damping, 0.05);
  EXPECT_EQ(rock.penalty, 3e9);
  EXPECT_EQ(rock.jkn, 40e9);
  EXPECT_EQ(rock.jks, 0.0);
  EXPECT_EQ(s.materials[1].name, "steel");
  EXPECT_EQ(s.materials[1].friction_angle, 20.0);

  // Keys the interaction gives override; the others follow the material table's mixing rule.
  ASSERT_EQ(s.interactions.size(), 1u);
  const setup::Setup::Interaction& in = s.interactions[0];
  EXPECT_EQ(in.a, 1);
  EXPECT_EQ(in.b, 0);
  EXPECT_EQ(in.properties.ks, 0.5e9);
  EXPECT_EQ(in.properties.friction_angle, 10.0);
  EXPECT_EQ(in.properties.jks, 2e10);
  EXPECT_EQ(in.properties.jkn, 0.0) << "the softer of 40 GPa/m and steel's none";
  EXPECT_EQ(in.properties.kn, std::min(rock.kn, s.materials[1].kn));
  EXPECT_EQ(in.properties.penalty, std::min(rock.penalty, s.materials[1].penalty));
  EXPECT_EQ(in.properties.normal_damping,
            0.5 * (rock.normal_damping + s.materials[1].normal_damping));

  ASSERT_EQ(s.shapes.size(), 4u);
  EXPECT_EQ(s.shapes[0].name, "brick");
  EXPECT_EQ(s.shapes[0].line, lineContaining(kFull, "[[shape]]", 0));
  EXPECT_EQ(s.shapes[0].vertices.size(), 8u);
  for (const Vec3& v : s.shapes[0].vertices) EXPECT_EQ(v.cwiseAbs(), Vec3(1e-3, 2e-3, 3e-3));
  std::set<std::array<double, 3>> slab;
  for (double x : {-1, 1}) {
    for (double y : {-1, 1}) {
      for (double z : {-1, 0}) slab.insert({x, y, z});
    }
  }
  EXPECT_EQ(asSet(s.shapes[1].vertices), slab);
  EXPECT_EQ(asSet(s.shapes[2].vertices),
            (std::set<std::array<double, 3>>{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}}));
  // Half-sizes (1, 2, 3), scaled by 0.5, turned 90 degrees about z.
  EXPECT_TRUE(extent(s.shapes[3].vertices).isApprox(Vec3(1.0, 0.5, 1.5), 1e-14));

  ASSERT_EQ(s.drivers.size(), 1u);
  const dynamics::DriverSpec& d = s.drivers[0];
  EXPECT_EQ(d.name, "shake");
  EXPECT_EQ(d.velocity, Vec3(0.1, 0, 0));
  EXPECT_DOUBLE_EQ(d.angular_velocity.z(), kPi);
  EXPECT_EQ(d.pivot, Vec3(0, 0, 1e-3));
  EXPECT_EQ(d.oscillation, Vec3(0, 0, 0.01));
  EXPECT_EQ(d.frequency, 5.0);
  EXPECT_DOUBLE_EQ(d.phase, 0.5 * kPi);
  EXPECT_EQ(d.start_time, 1.0);
  EXPECT_EQ(d.end_time, 3.0);
  EXPECT_EQ(d.line, lineContaining(kFull, "[[driver]]"));

  // base (uid 1), the 2 x 3 x 2 grid (uids 2..13, x fastest), top (uid 14).
  ASSERT_EQ(s.particles.size(), 14u);
  for (std::size_t i = 0; i < s.particles.size(); ++i) EXPECT_EQ(s.particles[i].uid, i + 1);
  const setup::ParticleSpec& base = s.particles[0];
  EXPECT_EQ(base.label, "base");
  EXPECT_EQ(base.shape, 1);
  EXPECT_EQ(base.material, 0);
  EXPECT_EQ(base.driver, 0);
  EXPECT_FALSE(base.fixed);
  EXPECT_EQ(base.position, Vec3::Zero());
  EXPECT_EQ(base.line, lineContaining(kFull, "[[particle]]", 0));
  for (int k = 0; k < 2; ++k) {
    for (int j = 0; j < 3; ++j) {
      for (int i = 0; i < 2; ++i) {
        const setup::ParticleSpec& p = s.particles[1 + i + 2 * j + 6 * k];
        EXPECT_EQ(p.label, cat("g_", i, "_", j, "_", k));
        EXPECT_EQ(p.shape, 0);
        EXPECT_EQ(p.material, 1);
        EXPECT_TRUE(p.position.isApprox(Vec3(3e-3 * i, 5e-3 * j, 1e-2 + 7e-3 * k), 1e-15));
        EXPECT_TRUE((p.orientation * Vec3::UnitX()).isApprox(Vec3::UnitY(), 1e-15));
        EXPECT_EQ(p.velocity, Vec3(0, 0, -1));
        EXPECT_EQ(p.line, lineContaining(kFull, "[[particle_grid]]"));
      }
    }
  }
  const setup::ParticleSpec& top = s.particles[13];
  EXPECT_EQ(top.label, "top");
  EXPECT_EQ(top.shape, 2);
  EXPECT_EQ(top.driver, -1);
  EXPECT_TRUE(top.fixed);
  EXPECT_EQ(top.position, Vec3(0, 0, 1));
  // 90 degrees about x, then the (normalised) quaternion [0, 0, 0, 2]: 180 degrees about z.
  EXPECT_TRUE((top.orientation * Vec3::UnitY()).isApprox(Vec3::UnitZ(), 1e-15));
  EXPECT_TRUE((top.orientation * Vec3::UnitX()).isApprox(-Vec3::UnitX(), 1e-15));
  EXPECT_EQ(top.velocity, Vec3(1e-3, 0, 0));
  EXPECT_EQ(top.angular_velocity, Vec3(0, 0.5, 0));

  EXPECT_EQ(s.output.series_every, 5);
  EXPECT_EQ(s.output.snapshot_every, 100);
  EXPECT_EQ(s.output.progress_every, 1000);
  EXPECT_EQ(s.output.monitor, (std::vector<std::string>{"top", "g_1_2_1"}));
  EXPECT_EQ(s.checkpoint.every_steps, 1000);
  EXPECT_EQ(s.checkpoint.every_seconds, 120.0);
  EXPECT_EQ(s.checkpoint.keep, 3);

  ASSERT_EQ(s.checks.size(), 2u);
  const setup::CheckSpec& c = s.checks[0];
  EXPECT_EQ(c.name, "drop");
  EXPECT_EQ(c.kind, "displacement");
  EXPECT_EQ(c.expected, 5e-3);
  EXPECT_EQ(c.tolerance, 1e-4);
  EXPECT_EQ(c.compare, "rel");
  EXPECT_EQ(c.reference, "eq. 1");
  EXPECT_EQ(c.strings, (std::map<std::string, std::string>{{"particle", "top"}, {"at", "end"}}));
  EXPECT_EQ(c.numbers, (std::map<std::string, std::vector<double>>{{"direction", {0, 1, 0}}}));
  EXPECT_EQ(c.line, lineContaining(kFull, "[[check]]", 0));
  EXPECT_EQ(s.checks[1].compare, "report");
  EXPECT_EQ(s.checks[1].expected, 0.0);
  // A rotation check's value is in radians: its tolerance is read as an angle in radians.
  EXPECT_NEAR(s.checks[1].tolerance, 3.14159265358979 / 180, 1e-15);
}

TEST(SceneReader, DefaultsFromTheSceneStruct) {
  const setup::Setup s = parseScene(kBase, "base.toml");
  const setup::Setup defaults;
  EXPECT_EQ(s.kernel, "gjk-epa-ipm");
  EXPECT_EQ(s.broadphase, defaults.broadphase);
  EXPECT_EQ(s.contact_point, "kernel");
  EXPECT_EQ(s.contact_model, "sub-contacts");
  EXPECT_EQ(s.gravity, defaults.gravity);
  EXPECT_FALSE(s.end_time);
  EXPECT_FALSE(s.equilibrium.enabled);
  EXPECT_FALSE(s.domain.min || s.domain.max || s.domain.blocks);
  EXPECT_EQ(s.output.series_every, defaults.output.series_every);
  EXPECT_EQ(s.checkpoint.keep, defaults.checkpoint.keep);
  EXPECT_EQ(s.particles[0].orientation.coeffs(), Quat::Identity().coeffs());
}

TEST(SceneReader, GridJitterIsSeededAndBounded) {
  const std::string grid = kBase + R"(
[[particle_grid]]
shape = "cube"
material = "rock"
origin = [0, 0, 5]
spacing = 2
count = [4, 4, 4]
jitter = "1 cm"
seed = 11
)";
  const setup::Setup a = parseScene(grid, "a.toml");
  const setup::Setup b = parseScene(grid, "b.toml");
  const setup::Setup c = parseScene(replaced(grid, "seed = 11", "seed = 12"), "c.toml");
  bool moved = false, differs = false;
  for (std::size_t n = 1; n < a.particles.size(); ++n) {
    const std::size_t i = (n - 1) % 4, j = (n - 1) / 4 % 4, k = (n - 1) / 16;
    const Vec3 lattice = Vec3(0, 0, 5) + 2.0 * Vec3(i, j, k);
    const Vec3 offset = a.particles[n].position - lattice;
    EXPECT_LE(offset.cwiseAbs().maxCoeff(), 1e-2);
    moved |= offset.cwiseAbs().maxCoeff() > 1e-3;
    EXPECT_EQ(a.particles[n].position, b.particles[n].position);  // same seed, same bits
    differs |= a.particles[n].position != c.particles[n].position;
  }
  EXPECT_TRUE(moved);
  EXPECT_TRUE(differs);
}

// Vertices of the one shape of a scene made of kBase plus this [[shape]] body.
std::vector<Vec3> shapeVertices(const std::string& body) {
  const std::string text = replaced(kBase, "type = \"cube\"\nedge = 1\n", body);
  return parseScene(text, "shape.toml").shapes.at(0).vertices;
}

Vec3 centroidOf(const std::vector<Vec3>& v) {
  return geometry::ConvexPolyhedron::fromPoints(v).centroid();
}

TEST(SceneReader, BuiltInShapesAreCentredOnTheirCentroid) {
  for (const char* body :
       {"type = \"triangular_prism\"\nlength = 2\nwidth = 1\nheight = 1.5\n",
        "type = \"pyramid\"\nbase = 1\nheight = 2\n",
        "type = \"pyramid\"\nbase = 1\nheight = 2\napex = \"down\"\n",
        "type = \"prism\"\npolygon = [[1, 1], [4, 1], [1, 3]]\nheight = 2\n",
        "type = \"hexagonal_prism\"\nradius = 0.5\nlength = 3\n",
        "type = \"random\"\ncount = 20\nradius = 2\nseed = 3\n",
        "type = \"tetrahedron\"\nedge = 1\n", "type = \"octahedron\"\nedge = 1\n",
        "type = \"dodecahedron\"\nedge = 1\n", "type = \"icosahedron\"\nedge = 1\n"}) {
    const std::vector<Vec3> v = shapeVertices(body);
    EXPECT_LT(centroidOf(v).norm(), 1e-14 * extent(v).norm()) << body;
  }
}

TEST(SceneReader, ShapeTypesFollowTheirDocumentedLayout) {
  // Triangular prism: ridge along x at z = 2h/3, base of the given width h below it.
  std::vector<Vec3> v = shapeVertices(
      "type = \"triangular_prism\"\nlength = 2\nwidth = 1\n"
      "height = 1.5\n");
  ASSERT_EQ(v.size(), 6u);
  for (const Vec3& p : v) {
    EXPECT_EQ(std::abs(p.x()), 1.0);
    const bool ridge = p.z() > 0;
    EXPECT_EQ(ridge ? p.z() : p.z() + 1.5, 1.0);
    EXPECT_EQ(std::abs(p.y()), ridge ? 0.0 : 0.5);
  }
  // Square pyramid: apex at 3h/4 above the centroid (up) or below it (down).
  for (const char* apex : {"up", "down"}) {
    v = shapeVertices(cat("type = \"pyramid\"\nbase = 1\nheight = 2\napex = \"", apex, "\"\n"));
    ASSERT_EQ(v.size(), 5u);
    const double sign = std::string(apex) == "up" ? 1.0 : -1.0;
    const auto tip = std::max_element(v.begin(), v.end(), [&](const Vec3& a, const Vec3& b) {
      return sign * a.z() < sign * b.z();
    });
    EXPECT_EQ(*tip, Vec3(0, 0, sign * 1.5));
    EXPECT_EQ(extent(v), Vec3(0.5, 0.5, 1.5));
  }
  // Hexagonal prism: axis along x, corner radius 0.5, a flat face down.
  v = shapeVertices("type = \"hexagonal_prism\"\nradius = 0.5\nlength = 3\n");
  ASSERT_EQ(v.size(), 12u);
  int bottom = 0;
  for (const Vec3& p : v) {
    EXPECT_DOUBLE_EQ(std::abs(p.x()), 1.5);
    EXPECT_NEAR(std::hypot(p.y(), p.z()), 0.5, 1e-15);
    bottom += std::abs(p.z() + 0.5 * std::sqrt(3.0) * 0.5) < 1e-15;
  }
  EXPECT_EQ(bottom, 4);
  // Cube: edge 2 gives corners at +-1; a vector scale stretches each axis.
  v = shapeVertices("type = \"cube\"\nedge = 2\nscale = [1, 2, 3]\n");
  ASSERT_EQ(v.size(), 8u);
  for (const Vec3& p : v) EXPECT_EQ(p.cwiseAbs(), Vec3(1, 2, 3));
  // Prism: the polygon's centroid moves to the axis, z spans the height.
  v = shapeVertices("type = \"prism\"\npolygon = [[1, 1], [3, 1], [3, 3], [1, 3]]\nheight = 2\n");
  ASSERT_EQ(v.size(), 8u);
  for (const Vec3& p : v) EXPECT_TRUE(p.cwiseAbs().isApprox(Vec3(1, 1, 1), 1e-15)) << p;
  // Random: count points on a sphere of the radius, centroid moved to the origin.
  v = shapeVertices("type = \"random\"\ncount = 12\nradius = \"5 mm\"\nseed = 1\n");
  EXPECT_EQ(v.size(), 12u);
  EXPECT_EQ(v, shapeVertices("type = \"random\"\ncount = 12\nradius = \"5 mm\"\nseed = 1\n"));
  EXPECT_LT(extent(v).maxCoeff(), 2 * 5e-3);
}

TEST(SceneReader, ExampleSceneParses) {
  const setup::Setup s = readScene(POLYDEM_SOURCE_DIR "/benchmark_scenes/examples/minimal.toml");
  EXPECT_EQ(s.id, "EX-MINIMAL");
  ASSERT_EQ(s.particles.size(), 2u);
  EXPECT_TRUE(s.particles[0].fixed);
  EXPECT_EQ(s.particles[1].position, Vec3(0, 0, 0.505));
  EXPECT_EQ(s.materials.at(0).kn, 1e10);
  EXPECT_EQ(s.materials.at(0).friction_angle, 30.0);
  EXPECT_EQ(s.output.monitor, std::vector<std::string>{"block"});
}

TEST(SceneReader, MissingFileIsAnInputError) {
  try {
    readScene("/nonexistent/scene.toml");
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), "/nonexistent/scene.toml");
    EXPECT_NE(std::string(e.what()).find("cannot open"), std::string::npos);
  }
}

}  // namespace
}  // namespace polydem::scene
