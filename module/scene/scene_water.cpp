// [water]: water pressure in the joints (docs/scene-format.md, "Water"): the unit weight of water
// and the phreatic surface (a level, the plane through three points, or a triangulated surface
// through more), fixed or against time, and [[water.joint]]: a surface of its own (or none) on
// the faces of some joints.
#include <algorithm>
#include <cmath>

#include "polydem/core/strings.h"
#include "polydem/geometry/plan_triangulation.h"
#include "polydem/scene/scene_sections.h"

namespace polydem::scene::detail {

namespace {

const toml::array& arrayAt(const Section& s, std::string_view key) {
  const toml::array* a = s.find(key)->as_array();
  if (!a) s.fail(key, "expected an array, got " + typeName(*s.find(key)));
  return *a;
}

// `points`: three or more [x, y, z] (a fixed surface) or, with a table, [x, y]. Three give the
// plane through them; more, their Delaunay triangulation in plan.
void readPoints(const Section& s, bool with_table, setup::WaterSurfaceSpec& w,
                std::vector<double>& heights) {
  const toml::array& a = arrayAt(s, "points");
  const std::size_t width = with_table ? 2 : 3;
  const char* form = with_table ? "[x, y] (the table gives their heights)" : "[x, y, z]";
  if (a.size() < 3) s.fail("points", cat("expected three points or more, each ", form));
  for (std::size_t i = 0; i < a.size(); ++i) {
    const std::string what = element(s.where("points"), i);
    const toml::array* p = a[i].as_array();
    if (!p || p->size() != width) {
      s.context().fail(lineOf(a[i]), cat(what, ": expected ", form, ", got ",
                                         p ? cat("an array of ", p->size()) : typeName(a[i])));
    }
    double c[3] = {0, 0, 0};
    for (std::size_t k = 0; k < width; ++k) {
      c[k] = toNumber(s.context(), (*p)[k], element(what, k), Quantity::kLength);
    }
    w.points.push_back({c[0], c[1]});
    if (!with_table) heights.push_back(c[2]);
  }
  if (a.size() > 3) {
    // A height over every (x, y) of the hull: no two points at one place, not all on a line.
    auto t = geometry::delaunayTriangulation(w.points);
    if (!t.error.empty()) s.fail("points", t.error + " (points counted from 1)");
    w.triangles = std::move(t.triangles);
    return;
  }
  // The plane must have a height over every (x, y): its points may not lie on one line in plan.
  const auto& p = w.points;
  const double ux = p[1][0] - p[0][0], uy = p[1][1] - p[0][1];
  const double vx = p[2][0] - p[0][0], vy = p[2][1] - p[0][1];
  const double scale = std::max(ux * ux + uy * uy, vx * vx + vy * vy);
  if (!(std::abs(ux * vy - uy * vx) > 1e-9 * scale)) {
    s.fail("points", "the three points lie on one line in plan (x, y): they give no plane");
  }
}

// `table`: rows [time, level] or [time, z1, .., zN], increasing in time.
void readTable(const Section& s, std::size_t heights, setup::WaterSurfaceSpec& w) {
  const toml::array& a = arrayAt(s, "table");
  const std::string form =
      heights == 1 ? "[time, level]" : cat("[time, z1 .. z", heights, "] (heights of the points)");
  if (a.empty()) s.fail("table", cat("expected rows ", form));
  for (std::size_t i = 0; i < a.size(); ++i) {
    const std::string what = element(s.where("table"), i);
    const toml::array* row = a[i].as_array();
    if (!row || row->size() != heights + 1) {
      s.context().fail(lineOf(a[i]), cat(what, ": expected ", form, ", got ",
                                         row ? cat("a row of ", row->size()) : typeName(a[i])));
    }
    const double t = toNumber(s.context(), (*row)[0], element(what, 0), Quantity::kTime);
    if (!w.times.empty() && !(t > w.times.back())) {
      s.context().fail(lineOf(a[i]),
                       cat(what, ": times must increase (", t, " s after ", w.times.back(), " s)"));
    }
    std::vector<double> z;
    for (std::size_t k = 1; k <= heights; ++k) {
      z.push_back(toNumber(s.context(), (*row)[k], element(what, k), Quantity::kLength));
    }
    w.times.push_back(t);
    w.heights.push_back(std::move(z));
  }
}

// The surface of `s`: level, points, table, or (where `dry_allowed`) dry = true. False when `s`
// gives none of them.
bool readSurface(const Section& s, bool dry_allowed, setup::WaterSurfaceSpec& w) {
  const bool with_table = s.has("table");
  const int given = s.has("level") + s.has("points") + (with_table && !s.has("points")) +
                    (dry_allowed && s.has("dry"));
  if (given > 1) {
    const char* key = s.has("level") ? "level" : "points";
    s.fail(dry_allowed && s.has("dry") ? "dry" : key,
           cat("give the surface once: level (fixed), points (a fixed plane or surface), table (a "
               "moving level), or points as [x, y] with a table (a moving surface)",
               dry_allowed ? ", or dry = true" : ""));
  }
  if (dry_allowed && s.has("dry")) {
    const auto dry = s.boolean("dry");
    if (!*dry) s.fail("dry", "write dry = true (no water on this joint), or give its surface");
    w.dry = true;
  } else if (s.has("level")) {
    w.times = {0.0};
    w.heights = {{s.requiredNumber("level", Quantity::kLength)}};
  } else if (s.has("points")) {
    std::vector<double> heights;
    readPoints(s, with_table, w, heights);
    if (with_table) {
      readTable(s, w.points.size(), w);
    } else {
      w.times = {0.0};
      w.heights = {heights};
    }
  } else if (with_table) {
    readTable(s, 1, w);
  } else {
    return false;
  }
  return true;
}

// The joint planes a [[water.joint]] name stands for: those of a [[joint]] of that name, or the
// [[rock_mass.plane]] or joint set of that name ("crack", or "mass/crack" in a scene of several
// rock masses).
std::vector<int> planesNamed(const std::string& name, const setup::Setup& scene) {
  std::vector<int> out;
  for (std::size_t k = 0; k < scene.joint_planes.size(); ++k) {
    const auto& plane = scene.joint_planes[k];
    const std::string bare = plane.name.substr(plane.name.find('/') + 1);
    const bool by_joint = plane.joint >= 0 && scene.joints[plane.joint].name == name;
    if (by_joint || plane.name == name || bare == name || bare.substr(0, bare.rfind('#')) == name ||
        plane.name.substr(0, plane.name.rfind('#')) == name) {
      out.push_back(static_cast<int>(k));
    }
  }
  return out;
}

void readWaterJoints(const Section& water, setup::Setup& scene) {
  const toml::node* n = water.find("joint");
  const toml::array* a = n->as_array();
  if (!a || !a->is_array_of_tables()) {
    water.fail("joint",
               "write [[water.joint]] sections, each with joint = \"NAME\" and its surface");
  }
  for (std::size_t i = 0; i < a->size(); ++i) {
    const Section s(water.context(), *(*a)[i].as_table(), cat("[[water.joint]] #", i + 1));
    s.allowOnly({"joint", "level", "points", "table", "dry"});
    setup::WaterJointSpec j;
    j.name = s.requiredString("joint");
    j.line = s.line();
    j.planes = planesNamed(j.name, scene);
    if (j.planes.empty()) {
      std::string known;
      for (const auto& joint : scene.joints) known += (known.empty() ? "" : ", ") + joint.name;
      for (const auto& plane : scene.joint_planes)
        known += (known.empty() ? "" : ", ") + plane.name;
      s.fail("joint", cat("no [[joint]] or rock mass plane is named '", j.name,
                          "' (known: ", known.empty() ? "none" : known, ")"));
    }
    for (const auto& other : scene.water.joints) {
      for (const int k : other.planes) {
        if (std::find(j.planes.begin(), j.planes.end(), k) != j.planes.end()) {
          s.fail("joint",
                 cat("plane ", scene.joint_planes[k].name,
                     " already has the surface of the [[water.joint]] at line ", other.line));
        }
      }
    }
    if (!readSurface(s, true, j.surface)) {
      s.failHere("give the joint's water: level, points, table, or dry = true");
    }
    scene.water.joints.push_back(std::move(j));
  }
}

}  // namespace

void readWater(const Context& ctx, const toml::table& root, setup::Setup& scene) {
  const toml::node* n = root.get("water");
  if (!n) return;
  const toml::table* t = n->as_table();
  if (!t) ctx.fail(lineOf(*n), "'water' must be a table: write [water], got " + typeName(*n));
  const Section s(ctx, *t, "[water]");
  s.allowOnly({"unit_weight", "level", "points", "table", "joint"});
  setup::WaterSpec& w = scene.water;
  w.enabled = true;
  w.line = s.line();
  w.unit_weight = s.number("unit_weight", Quantity::kUnitWeight, w.unit_weight, Range::kPositive);
  if (s.has("joint")) readWaterJoints(s, scene);
  if (!readSurface(s, false, w)) {
    // Without a surface of its own the water is only where [[water.joint]] puts it.
    if (w.joints.empty()) s.failHere("give the phreatic surface: level, points, or table");
    w.dry = true;
  }
}

}  // namespace polydem::scene::detail
