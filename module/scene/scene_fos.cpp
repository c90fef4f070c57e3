// [fos]: the settings of `polydem fos` (strength reduction, run/fos.h) in a scene file.
#include <limits>

#include "polydem/core/strings.h"
#include "polydem/scene/scene_sections.h"

namespace polydem::scene::detail {

namespace {

// [fos] joints = ["base", ...]: the [[joint]]s reduced, by name.
void readFosJoints(const Context& ctx, const Section& s, const toml::node& list,
                   setup::Setup& scene) {
  const toml::array* a = list.as_array();
  if (!a) s.fail("joints", "expected a list of [[joint]] names, as in [\"base\", \"bedding\"]");
  setup::FosSpec& f = scene.fos;
  f.joints_named = true;
  for (std::size_t i = 0; i < a->size(); ++i) {
    const std::string what = element(s.where("joints"), i);
    const toml::node& e = (*a)[i];
    if (!e.is_string()) ctx.fail(lineOf(e), what + ": expected the name of a [[joint]]");
    const std::string name = e.as_string()->get();
    const int index = indexByName(scene.joints, name);
    if (index < 0) {
      std::string known;
      for (const auto& j : scene.joints) known += (known.empty() ? "'" : ", '") + j.name + "'";
      ctx.fail(lineOf(e), what + ": no [[joint]] is named '" + name + "' (" +
                              (known.empty() ? "the scene has none" : "known: " + known) + ")");
    }
    for (std::size_t k = 0; k < f.joints.size(); ++k) {
      if (f.joints[k] == index) ctx.fail(lineOf(e), what + ": '" + name + "' is named twice");
    }
    f.joints.push_back(index);
    f.joint_lines.push_back(lineOf(e));
  }
}

}  // namespace

void readFos(const Context& ctx, const toml::table& root, setup::Setup& scene) {
  const toml::node* n = root.get("fos");
  if (!n) return;
  const toml::table* t = n->as_table();
  if (!t) ctx.fail(lineOf(*n), "'fos' must be a table: write [fos], got " + typeName(*n));
  const Section s(ctx, *t, "[fos]");
  s.allowOnly({"interactions", "joints", "f_min", "f_max", "resolution", "max_time", "time_cap",
               "settle_time", "force_ratio", "speed_decay", "local_damping", "speed_limit",
               "displacement_limit", "check_every", "label_prefix", "reduce_bolts"});
  setup::FosSpec& f = scene.fos;
  f.line = s.line();
  if (const toml::node* list = s.find("interactions")) {
    const toml::array* a = list->as_array();
    if (!a)
      s.fail("interactions", "expected a list of material pairs, as in [[\"rock\", \"rock\"]]");
    for (std::size_t i = 0; i < a->size(); ++i) {
      const std::string what = element(s.where("interactions"), i);
      const toml::array* pair = (*a)[i].as_array();
      if (!pair || pair->size() != 2 || !(*pair)[0].is_string() || !(*pair)[1].is_string()) {
        ctx.fail(lineOf((*a)[i]),
                 what + ": expected two material names, as in [\"rock\", \"rock\"]");
      }
      int index[2];
      for (int k = 0; k < 2; ++k) {
        const std::string name = (*pair)[k].as_string()->get();
        index[k] = indexByName(scene.materials, name);
        if (index[k] < 0)
          ctx.fail(lineOf((*pair)[k]), what + ": no [[material]] is named '" + name + "'");
      }
      f.interactions.emplace_back(std::min(index[0], index[1]), std::max(index[0], index[1]));
      f.interaction_lines.push_back(lineOf((*a)[i]));
    }
  }
  if (const toml::node* list = s.find("joints")) readFosJoints(ctx, s, *list, scene);
  f.f_min = s.number("f_min", Quantity::kDimensionless, f.f_min, Range::kPositive);
  f.f_max = s.number("f_max", Quantity::kDimensionless, f.f_max, Range::kPositive);
  if (!(f.f_max > f.f_min)) s.fail("f_max", "must exceed f_min");
  f.resolution = s.number("resolution", Quantity::kDimensionless, f.resolution, Range::kPositive);
  f.max_time = s.number("max_time", Quantity::kTime, Range::kPositive);
  f.max_time_line = s.lineOf("max_time");
  f.time_cap = s.number("time_cap", Quantity::kTime, Range::kPositive);
  f.settle_time = s.number("settle_time", Quantity::kTime, Range::kPositive);
  if (f.max_time && f.settle_time && !(*f.settle_time < *f.max_time)) {
    s.fail("settle_time", "must be shorter than max_time");
  }
  if (f.max_time && f.time_cap && *f.time_cap < *f.max_time) {
    s.fail("time_cap", "must be at least max_time (undecided trials run on from max_time to it)");
  }
  f.force_ratio =
      s.bounded("force_ratio", Quantity::kDimensionless, f.force_ratio, 0.0, 1.0, false);
  if (!(f.force_ratio > 0)) s.fail("force_ratio", "must be > 0");
  f.speed_decay =
      s.bounded("speed_decay", Quantity::kDimensionless, f.speed_decay, 0.0, 1.0, false);
  if (!(f.speed_decay > 0)) s.fail("speed_decay", "must be > 0");
  if (s.has("local_damping")) {
    f.local_damping = s.bounded("local_damping", Quantity::kDimensionless, 0.8, 0.0, 1.0, false);
  }
  f.speed_limit = s.number("speed_limit", Quantity::kVelocity, Range::kPositive);
  f.displacement_limit = s.number("displacement_limit", Quantity::kLength, Range::kPositive);
  f.check_every = s.integer("check_every", f.check_every, Range::kPositive);
  f.check_every_line = s.lineOf("check_every");
  f.label_prefix = s.string("label_prefix").value_or("");
  f.reduce_bolts = s.boolean("reduce_bolts").value_or(false);
}

}  // namespace polydem::scene::detail
