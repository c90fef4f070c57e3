// [water]: water pressure in the joints (docs/scene-format.md, "Water"): the unit weight of water
// and the phreatic surface (a level, or a plane through three points), fixed or against time.
#include <cmath>

#include "polydem/core/strings.h"
#include "polydem/scene/scene_sections.h"

namespace polydem::io::detail {

namespace {

const toml::array& arrayAt(const Section& s, std::string_view key) {
  const toml::array* a = s.find(key)->as_array();
  if (!a) s.fail(key, "expected an array, got " + typeName(*s.find(key)));
  return *a;
}

// `points`: three [x, y, z] (a fixed plane) or, with a table, three [x, y].
void readPoints(const Section& s, bool with_table, WaterSpec& w, std::vector<double>& heights) {
  const toml::array& a = arrayAt(s, "points");
  const std::size_t width = with_table ? 2 : 3;
  const char* form = with_table ? "[x, y] (the table gives their heights)" : "[x, y, z]";
  if (a.size() != 3) s.fail("points", cat("expected three points, each ", form));
  for (std::size_t i = 0; i < 3; ++i) {
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
  // The plane must have a height over every (x, y): its points may not lie on one line in plan.
  const auto& p = w.points;
  const double ux = p[1][0] - p[0][0], uy = p[1][1] - p[0][1];
  const double vx = p[2][0] - p[0][0], vy = p[2][1] - p[0][1];
  const double scale = std::max(ux * ux + uy * uy, vx * vx + vy * vy);
  if (!(std::abs(ux * vy - uy * vx) > 1e-9 * scale)) {
    s.fail("points", "the three points lie on one line in plan (x, y): they give no plane");
  }
}

// `table`: rows [time, level] or [time, z1, z2, z3], increasing in time.
void readTable(const Section& s, std::size_t heights, WaterSpec& w) {
  const toml::array& a = arrayAt(s, "table");
  const char* form = heights == 1 ? "[time, level]" : "[time, z1, z2, z3] (heights of the points)";
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

}  // namespace

void readWater(const Context& ctx, const toml::table& root, Scene& scene) {
  const toml::node* n = root.get("water");
  if (!n) return;
  const toml::table* t = n->as_table();
  if (!t) ctx.fail(lineOf(*n), "'water' must be a table: write [water], got " + typeName(*n));
  const Section s(ctx, *t, "[water]");
  s.allowOnly({"unit_weight", "level", "points", "table"});
  WaterSpec& w = scene.water;
  w.enabled = true;
  w.line = s.line();
  w.unit_weight = s.number("unit_weight", Quantity::kUnitWeight, w.unit_weight, Range::kPositive);
  const bool with_table = s.has("table");
  if (s.has("level") && (s.has("points") || with_table)) {
    s.fail("level",
           "give the surface once: level (fixed), points (a fixed plane), table (a "
           "moving level), or points as [x, y] with a table (a moving plane)");
  }
  if (s.has("level")) {
    w.times = {0.0};
    w.heights = {{s.requiredNumber("level", Quantity::kLength)}};
  } else if (s.has("points")) {
    std::vector<double> heights;
    readPoints(s, with_table, w, heights);
    if (with_table) {
      readTable(s, 3, w);
    } else {
      w.times = {0.0};
      w.heights = {heights};
    }
  } else if (with_table) {
    readTable(s, 1, w);
  } else {
    s.failHere("give the phreatic surface: level, points, or table");
  }
}

}  // namespace polydem::io::detail
