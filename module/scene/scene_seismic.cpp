// [seismic]: the earthquake (docs/scene-format.md "Earthquakes"): the pseudo-static load
// (horizontal and vertical seismic coefficients as fractions of g, and the azimuth of the
// horizontal load), or an acceleration record that moves the fixed rock
// (scene_ground_record.cpp).
#include "polydem/core/strings.h"
#include "polydem/scene/scene_sections.h"

namespace polydem::scene::detail {

void readSeismic(const Context& ctx, const toml::table& root, setup::Setup& scene) {
  const toml::node* n = root.get("seismic");
  if (!n) return;
  const toml::table* t = n->as_table();
  if (!t) ctx.fail(lineOf(*n), "'seismic' must be a table: write [seismic], got " + typeName(*n));
  const Section s(ctx, *t, "[seismic]");
  s.allowOnly({"kh", "azimuth", "kv", "record", "record_x", "record_y", "record_z", "time_step",
               "units", "scale"});
  setup::SeismicSpec& e = scene.seismic;
  e.enabled = true;
  e.line = s.line();
  if (readGroundRecord(s, scene, e)) return;
  e.kh = s.bounded("kh", Quantity::kDimensionless, 0.0, 0.0, 1.0, true);
  e.kv = s.bounded("kv", Quantity::kDimensionless, 0.0, -1.0, 1.0, true);
  // A horizontal load without its direction would be a silent guess: the azimuth is required.
  if (s.has("kh") && !s.has("azimuth")) {
    s.fail("kh",
           "give the azimuth of the horizontal load too (degrees clockwise from north = "
           "+y, the direction it pushes: the slope's dip direction for a load out of it)");
  }
  e.azimuth = s.bounded("azimuth", Quantity::kAngle, 0.0, 0.0, 360.0, false);
  if (!s.has("kh") && !s.has("kv")) {
    s.failHere("give kh (with its azimuth), kv, or both; or an acceleration record");
  }
  if ((e.kh != 0.0 || e.kv != 0.0) && !(scene.gravity.norm() > 0.0)) {
    s.failHere("the coefficients are fractions of g, but [simulation] gravity is zero");
  }
}

}  // namespace polydem::scene::detail
