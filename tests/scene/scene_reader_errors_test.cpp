// The scene reader on invalid input: every class of error is an InputError at the line marked
// "# <-" in the text, with a message naming the table and key.
#include <gtest/gtest.h>

#include "polydem/contact/contact.h"
#include "polydem/core/strings.h"
#include "scene_test_support.h"

namespace polydem::scene {
namespace {

using namespace scene_test;

TEST(SceneReaderErrors, TomlSyntax) {
  expectError(replaced(kBase, "steps = 10", "steps = = 10  # <-"), {"TOML syntax error"});
}

TEST(SceneReaderErrors, UnknownKeys) {
  expectError(replaced(kBase, "steps = 10", "steps = 10\ndtt = 1  # <-"),
              {"[simulation]: unknown key 'dtt'", "did you mean 'dt'"});
  expectError(kBase + "[simulaton]  # <-\ndt = 1\n", {"top level: unknown key 'simulaton'"});
  expectError(replaced(kBase, "kn = 1e9", "kn = 1e9\ncolour = \"grey\"  # <-"),
              {"[[material]] 'rock': unknown key 'colour'", "known keys: name, density"});
  // Inside an inline table, and inside one element of an array of them.
  expectError(kBase + "rotation = { axis = [0, 0, 1], angel = 45 }  # <-\n",
              {"[[particle]] 'a' rotation: unknown key 'angel'"});
  expectError(kBase +
                  "rotation = [{ axis = [0, 0, 1], angle = 4 },\n"
                  "            { quaternion = [1, 0, 0, 0], w = 1 }]  # <-\n",
              {"rotation[1]: unknown key 'w'"});
  // Keys of another shape type are unknown for this one.
  expectError(replaced(kBase, "edge = 1", "edge = 1\nradius = 2  # <-"),
              {"[[shape]] 'cube': unknown key 'radius'"});
}

TEST(SceneReaderErrors, WrongTypes) {
  expectError(replaced(kBase, "density = 2500", "density = \"heavy\"  # <-"),
              {"[[material]] 'rock' density", "cannot read 'heavy' as a density"});
  expectError(replaced(kBase, "label = \"a\"", "label = 5  # <-"),
              {"[[particle]] #1 label: expected a string, got 5"});
  expectError(kBase + "fixed = \"yes\"  # <-\n", {"fixed: expected true or false"});
  expectError(kBase + "position = [0, 0]  # <-\n", {"position: expected an array of 3"});
  expectError(replaced(kBase, "steps = 10", "steps = 10.5  # <-"),
              {"steps: expected an integer, got 10.5"});
  expectError(kBase + "position = [0, 0, true]  # <-\n",
              {"position[2]: expected a length (m), got a boolean"});
  expectError(kBase + "[output]\nmonitor = \"a\"  # <-\n", {"expected an array of strings"});
  expectError(replaced(kBase, "[[material]]", "[material]  # <-"),
              {"'material' must be an array of tables", "[[material]]"});
  expectError(replaced(kBase, "[simulation]", "[[simulation]]  # <-"),
              {"'simulation' must be a table"});
  expectError(kBase + "[domain]\noverlap_exchange = \"yes\"  # <-\n",
              {"[domain]", "overlap_exchange: expected true or false"});
}

TEST(SceneReaderErrors, MissingRequiredValues) {
  expectError(replaced(replaced(kBase, "dt = 1e-4\n", ""), "[simulation]", "[simulation]  # <-"),
              {"[simulation]: missing required key 'dt'"});
  expectError(replaced(replaced(kBase, "steps = 10\n", ""), "[simulation]", "[simulation]  # <-"),
              {"give end_time or steps"});
  expectError(
      replaced(replaced(kBase, "density = 2500\n", ""), "[[material]]", "[[material]]  # <-"),
      {"[[material]] 'rock': missing required key 'density'"});
  expectError(
      replaced(replaced(kBase, "shape = \"cube\"\n", ""), "[[particle]]", "[[particle]]  # <-"),
      {"missing required key 'shape'"});
  expectError(replaced(kBase, "id = \"T-BASE\"", "id = \"\"  # <-"), {"id: must not be empty"});
  const InputError e = errorOf(replaced(kBase, "[scene]\nid = \"T-BASE\"\n", ""));
  EXPECT_EQ(e.line(), 0);
  EXPECT_NE(std::string(e.what()).find("missing the [scene] table"), std::string::npos);
}

TEST(SceneReaderErrors, UndefinedReferences) {
  expectError(replaced(kBase, "shape = \"cube\"", "shape = \"sphere\"  # <-"),
              {"[[particle]] 'a' shape: no [[shape]] is named 'sphere'"});
  expectError(replaced(kBase, "material = \"rock\"", "material = \"granite\"  # <-"),
              {"no [[material]] is named 'granite'"});
  expectError(kBase + "driver = \"tilt\"  # <-\n", {"no [[driver]] is named 'tilt'"});
  expectError(kBase + "[output]\nmonitor = [\"a\", \"b\"]  # <-\n",
              {"[output] monitor: no particle is labelled 'b'"});
  expectError(kBase + "[[interaction]]\nmaterials = [\"rock\", \"steel\"]  # <-\n",
              {"materials[1]: no [[material]] is named 'steel'"});
  expectError(kBase +
                  "[[particle_grid]]\nshape = \"cube\"\nmaterial = \"sand\"  # <-\n"
                  "spacing = 1\ncount = [1, 1, 1]\n",
              {"[[particle_grid]] #1 material: no [[material]] is named 'sand'"});
}

TEST(SceneReaderErrors, DuplicateNamesAndLabels) {
  const int first_material = lineContaining(kBase, "[[material]]");
  expectError(kBase + "[[material]]\nname = \"rock\"  # <-\ndensity = 1\nkn = 1\n",
              {"material 'rock' is already defined at line " + std::to_string(first_material)});
  expectError(kBase + "[[shape]]\nname = \"cube\"  # <-\ntype = \"cube\"\nedge = 2\n",
              {"shape 'cube' is already defined at line"});
  const std::string driver = "[[driver]]\nname = \"d\"\n";
  expectError(kBase + driver + "[[driver]]\nname = \"d\"  # <-\n",
              {"driver 'd' is already defined at line"});
  expectError(kBase + "[[particle]]\nlabel = \"a\"  # <-\nshape = \"cube\"\nmaterial = \"rock\"\n",
              {"the label 'a' is already used at line " +
               std::to_string(lineContaining(kBase, "[[particle]]"))});
  // A grid's generated label clashing with an earlier particle.
  expectError(replaced(kBase, "label = \"a\"", "label = \"g_0_0_0\"") +
                  "[[particle_grid]]\nshape = \"cube\"\nmaterial = \"rock\"\n"
                  "label_prefix = \"g\"  # <-\nspacing = 1\ncount = [2, 1, 1]\n",
              {"the label 'g_0_0_0' is already used"});
  expectError(kBase +
                  "[[interaction]]\nmaterials = [\"rock\", \"rock\"]\n"
                  "[[interaction]]\nmaterials = [\"rock\", \"rock\"]  # <-\n",
              {"the pair is already given at line"});
  const std::string check = "[[check]]\nname = \"c\"\nkind = \"mean_speed\"\nexpected = 1\n";
  expectError(
      kBase + check + "[[check]]\nname = \"c\"  # <-\nkind = \"mean_speed\"\nexpected = 1\n",
      {"check 'c' is already defined at line"});
}

TEST(SceneReaderErrors, NonFiniteValues) {
  expectError(replaced(kBase, "dt = 1e-4", "dt = nan  # <-"), {"dt: must be finite"});
  expectError(kBase + "position = [0, 0, -inf]  # <-\n", {"position[2]: must be finite"});
  expectError(kBase + "velocity = [\"inf m/s\", 0, 0]  # <-\n",
              {"velocity[0]: cannot read 'inf m/s'", "not finite"});
}

TEST(SceneReaderErrors, RangesAndPositivity) {
  expectError(replaced(kBase, "density = 2500", "density = 0  # <-"),
              {"[[material]] 'rock' density: must be > 0, got 0"});
  expectError(replaced(kBase, "dt = 1e-4", "dt = \"-1 ms\"  # <-"),
              {"[simulation] dt: must be > 0, got '-1 ms'"});
  expectError(replaced(kBase, "kn = 1e9", "kn = 1e9\nks = -1  # <-"), {"ks: must be >= 0"});
  expectError(replaced(replaced(kBase, "kn = 1e9", "kn = 0"), "[[material]]", "[[material]]  # <-"),
              {"needs kn > 0 (penalty kernels) or penalty > 0 (potential kernels)"});
  expectError(replaced(kBase, "kn = 1e9", "kn = 1e9\nfriction_angle = \"95 deg\"  # <-"),
              {"friction_angle: must lie in [0, 90) degrees, got '95 deg'"});
  expectError(kBase +
                  "[[particle_grid]]\nshape = \"cube\"\nmaterial = \"rock\"\nspacing = 1\n"
                  "count = [2, 0, 1]  # <-\n",
              {"count[1]: must be > 0"});
  expectError(replaced(kBase, "edge = 1", "edge = \"-2 mm\"  # <-"), {"edge: must be > 0"});
  expectError(kBase + "[[driver]]\nname = \"d\"\nstart_time = 2\nend_time = 1  # <-\n",
              {"end_time: must be later than start_time"});
  expectError(kBase + "[[driver]]\nname = \"d\"\noscillation = [0, 0, 1]  # <-\n",
              {"oscillation: needs frequency > 0"});
  expectError(kBase + "fixed = true\ndriver = \"d\"  # <-\n[[driver]]\nname = \"d\"\n",
              {"either fixed or driven"});
  expectError(kBase + "[domain]\nperiodic = [true, false, false]  # <-\n",
              {"a periodic axis needs the domain's min and max"});
  expectError(kBase + "[domain]\nmin = [0, 0, 0]\nmax = [1, 0, 1]  # <-\n",
              {"max: must exceed min"});
  expectError(kBase + "rotation = { axis = [0, 0, 0], angle = 3 }  # <-\n",
              {"axis: must not be zero"});
  expectError(kBase + "rotation = { axis = [0, 0, 1], angle = 3, euler_zyx = [0, 0, 0] }  # <-\n",
              {"give exactly one of"});
}

TEST(SceneReaderErrors, UnitsOfTheWrongDimension) {
  expectError(
      replaced(kBase, "kn = 1e9", "kn = \"2 GPa\"  # <-"),
      {"[[material]] 'rock' kn", "expected a stiffness (N/m)", "got '2 GPa'", "a pressure (Pa)"});
  expectError(replaced(kBase, "dt = 1e-4", "dt = \"1 mm\"  # <-"),
              {"dt: expected a time (s), got '1 mm', which is a length (m)"});
  expectError(kBase + "angular_velocity = [0, 0, \"2 Hz\"]  # <-\n",
              {"expected an angular velocity", "a frequency (Hz)"});
  expectError(replaced(kBase, "kn = 1e9", "kn = \"2 furlongs\"  # <-"),
              {"unknown unit 'furlongs'"});
}

TEST(SceneReaderErrors, NamesOutsideTheirLists) {
  const InputError e = errorOf(replaced(kBase, "kernel = \"gjk-epa-ipm\"", "kernel = \"gjk\""));
  EXPECT_EQ(e.line(), lineContaining(kBase, "kernel ="));
  EXPECT_NE(std::string(e.what()).find("'gjk' is not one of " + join(contact::kernelNames(), ", ")),
            std::string::npos)
      << e.what();
  expectError(replaced(kBase, "steps = 10", "steps = 10\nbroadphase = \"octree\"  # <-"),
              {"'octree' is not one of multilevel, nbs, all-pairs"});
  expectError(replaced(kBase, "steps = 10", "steps = 10\ncontact_point = \"ipm\"  # <-"),
              {"'ipm' is not one of kernel, overlap-centroid"});
  expectError(replaced(kBase, "steps = 10", "steps = 10\ncontact_model = \"3dec\"  # <-"),
              {"'3dec' is not one of sub-contacts, point"});
  expectError(
      replaced(kBase, "steps = 10", "steps = 10\ncontact_point = \"overlap-centroid\"  # <-"),
      {"contact_point", "needs contact_model = \"point\""});
  // A joint stiffness (per area) serves face contacts only: edge and corner contacts need kn, ks.
  expectError(replaced(kBase, "kn = 1e9", "kn = 1e9\njks = \"1 GPa/m\"  # <-"),
              {"jks", "needs ks > 0 too"});
  expectError(replaced(kBase, "kn = 1e9", "kn = 1e9\nks = 1e9\njks = \"1 GPa\"  # <-"),
              {"jks", "stiffness per area (Pa/m)"});
  expectError(replaced(kBase, "type = \"cube\"", "type = \"sphere\"  # <-"),
              {"type: 'sphere' is not one of box, vertices"});
  expectError(kBase +
                  "[[check]]\nname = \"c\"\nkind = \"mean_speed\"\nexpected = 1\n"
                  "compare = \"approx\"  # <-\n",
              {"'approx' is not one of abs, rel, max, min, report"});
  expectError(kBase + "[[check]]  # <-\nname = \"c\"\nkind = \"mean_speed\"\n",
              {"missing required key 'expected'"});
}

TEST(SceneReaderErrors, InvalidShapesAtTheShapeLine) {
  // Coplanar points: the geometry's GeometryError becomes an InputError at the [[shape]] line.
  expectError(replaced(kBase, "[[shape]]\nname = \"cube\"\ntype = \"cube\"\nedge = 1",
                       "[[shape]]  # <-\nname = \"cube\"\ntype = \"vertices\"\n"
                       "vertices = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]]"),
              {"[[shape]] 'cube': invalid shape"});
  expectError(replaced(kBase, "type = \"cube\"\nedge = 1",
                       "type = \"prism\"\nheight = 1\n"
                       "polygon = [[0, 0], [2, 0], [1, 0.2], [1, 2]]  # <-"),
              {"polygon: the polygon is not convex"});
  expectError(replaced(kBase, "[[shape]]\nname = \"cube\"\ntype = \"cube\"\nedge = 1",
                       "[[shape]]  # <-\nname = \"cube\"\ntype = \"box\"\nsize = [1, 1, 1]\n"
                       "min = [0, 0, 0]"),
              {"give either size = [x, y, z] or min and max"});
  // A point count that would exhaust memory is refused before anything is allocated.
  const std::string random = "type = \"random\"\nradius = 1\ncount = ";
  expectError(replaced(kBase, "type = \"cube\"\nedge = 1", random + "2000000000  # <-"),
              {"[[shape]] 'cube' count", "2000000000 is above the limit of 100000 points"});
  expectError(replaced(kBase, "type = \"cube\"\nedge = 1", random + "100001  # <-"),
              {"100001 is above the limit of 100000 points"});
}

}  // namespace
}  // namespace polydem::scene
