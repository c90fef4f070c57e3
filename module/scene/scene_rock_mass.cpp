// [[rock_mass]]: a region cut by [[rock_mass.joint_set]] and [[rock_mass.plane]] entries into
// blocks (geometry/rock_mass.h). Each block becomes a shape of its own and a particle, fixed where
// a plane says so. Syntax in docs/scene-format.md.
#include <algorithm>
#include <cmath>
#include <limits>
#include <new>

#include "polydem/core/error.h"
#include "polydem/core/interrupt.h"
#include "polydem/core/logging.h"
#include "polydem/core/strings.h"
#include "polydem/geometry/rock_mass.h"
#include "polydem/scene/scene_sections.h"

namespace polydem::scene::detail {

namespace {

// The entries of an array of tables inside a table ([[rock_mass.joint_set]]).
std::vector<Section> nestedEntries(const Section& parent, std::string_view key,
                                   const std::string& what) {
  std::vector<Section> out;
  const toml::node* n = parent.find(key);
  if (!n) return out;
  const toml::array* a = n->as_array();
  if (!a || (!a->empty() && !a->is_array_of_tables())) {
    parent.fail(key, cat("must be an array of tables: write [[rock_mass.", key, "]] sections"));
  }
  for (std::size_t i = 0; i < a->size(); ++i) {
    const toml::table& t = *(*a)[i].as_table();
    const toml::node* name = t.get("name");
    const bool named = name && name->is_string() && !name->as_string()->get().empty();
    out.emplace_back(parent.context(), t,
                     cat(parent.name(), " ", what, " ",
                         named ? "'" + name->as_string()->get() + "'" : cat("#", i + 1)));
  }
  return out;
}

const toml::array& pointList(const Section& s, std::string_view key) {
  if (!s.has(key)) s.missing(key);
  const toml::array* a = s.find(key)->as_array();
  if (!a) s.fail(key, "expected an array of points, got " + typeName(*s.find(key)));
  return *a;
}

geometry::RockRegion readRegion(const Section& mass) {
  if (!mass.has("region")) mass.missing("region");
  const toml::table* t = mass.find("region")->as_table();
  if (!t) {
    mass.fail("region",
              "expected a table, as in region = { type = \"box\", min = [..], max = [..] }");
  }
  const Section s(mass.context(), *t, mass.name() + " region");
  const std::string type = s.choice("type", {"box", "polyhedron", "profile"}, "");
  if (type.empty()) s.missing("type");
  const Context& ctx = s.context();
  try {
    if (type == "box") {
      s.allowOnly({"type", "min", "max"});
      if (!s.has("min")) s.missing("min");
      if (!s.has("max")) s.missing("max");
      const Vec3 lo = *s.vec3("min", Quantity::kLength), hi = *s.vec3("max", Quantity::kLength);
      if (!((hi - lo).array() > 0.0).all()) s.fail("max", "must exceed min in every coordinate");
      return geometry::boxRegion(lo, hi);
    }
    if (type == "polyhedron") {
      s.allowOnly({"type", "vertices"});
      const toml::array& a = pointList(s, "vertices");
      std::vector<Vec3> points;
      for (std::size_t i = 0; i < a.size(); ++i) {
        points.push_back(toVec3(ctx, a[i], element(s.where("vertices"), i), Quantity::kLength));
      }
      return geometry::polyhedronRegion(points);
    }
    s.allowOnly({"type", "profile", "y"});
    const toml::array& a = pointList(s, "profile");
    std::vector<Vec2> profile;
    for (std::size_t i = 0; i < a.size(); ++i) {
      const std::string what = element(s.where("profile"), i);
      const toml::array* xz = a[i].as_array();
      if (!xz || xz->size() != 2) {
        ctx.fail(lineOf(a[i]), what + ": expected a point [x, z], got " + typeName(a[i]));
      }
      profile.emplace_back(toNumber(ctx, (*xz)[0], what + "[0]", Quantity::kLength),
                           toNumber(ctx, (*xz)[1], what + "[1]", Quantity::kLength));
    }
    if (!s.has("y")) s.missing("y");
    const toml::array* y = s.find("y")->as_array();
    if (!y || y->size() != 2) s.fail("y", "expected [y_min, y_max]");
    const double y0 = toNumber(ctx, (*y)[0], s.where("y") + "[0]", Quantity::kLength);
    const double y1 = toNumber(ctx, (*y)[1], s.where("y") + "[1]", Quantity::kLength);
    if (!(y1 > y0)) s.fail("y", "y_max must exceed y_min");
    return geometry::profileRegion(profile, y0, y1);
  } catch (const GeometryError& e) {
    s.failHere(std::string("invalid region: ") + e.what());
  }
}

// dip and dip_direction of a joint set or a plane.
void readOrientation(const Section& s, double& dip, double& dip_direction) {
  if (!s.has("dip")) s.missing("dip");
  if (!s.has("dip_direction")) s.missing("dip_direction");
  dip = s.bounded("dip", Quantity::kAngle, 0.0, 0.0, 90.0, true);
  dip_direction = s.requiredNumber("dip_direction", Quantity::kAngle);
}

geometry::JointSet readJointSet(const Section& s) {
  s.allowOnly({"name", "dip", "dip_direction", "spacing", "offset", "origin", "spacing_jitter",
               "orientation_jitter", "fisher_k", "seed", "joint"});
  geometry::JointSet j;
  j.name = s.requiredString("name");
  readOrientation(s, j.dip, j.dip_direction);
  j.spacing = s.requiredNumber("spacing", Quantity::kLength, Range::kPositive);
  j.offset = s.number("offset", Quantity::kLength, 0.0);
  j.origin = s.vec3("origin", Quantity::kLength).value_or(j.origin);
  j.spacing_jitter = s.bounded("spacing_jitter", Quantity::kDimensionless, 0.0, 0.0, 1.0, false);
  j.orientation_jitter = s.bounded("orientation_jitter", Quantity::kAngle, 0.0, 0.0, 90.0, false);
  j.fisher_k = s.number("fisher_k", Quantity::kDimensionless, 0.0, Range::kNonNegative);
  if (j.fisher_k > 0.0 && j.orientation_jitter > 0.0) {
    s.fail("fisher_k", "orientation_jitter is given too: they scatter the same normals, give one");
  }
  j.seed = static_cast<std::uint64_t>(s.integer("seed", 0, Range::kNonNegative));
  return j;
}

geometry::Side readSide(const Section& s, std::string_view key) {
  const std::string side = s.choice(std::string(key), {"none", "below", "above"}, "none");
  if (side == "below") return geometry::Side::kBelow;
  if (side == "above") return geometry::Side::kAbove;
  return geometry::Side::kNone;
}

geometry::SinglePlane readPlane(const Section& s) {
  s.allowOnly({"name", "dip", "dip_direction", "point", "fixed", "remove", "joint"});
  geometry::SinglePlane p;
  p.name = s.requiredString("name");
  double dip = 0.0, dip_direction = 0.0;
  readOrientation(s, dip, dip_direction);
  if (!s.has("point")) s.missing("point");
  const Vec3 point = *s.vec3("point", Quantity::kLength);
  p.plane.normal = geometry::normalFromDip(dip, dip_direction);
  p.plane.offset = p.plane.normal.dot(point);
  p.fixed = readSide(s, "fixed");
  p.remove = readSide(s, "remove");
  if (p.fixed != geometry::Side::kNone && p.fixed == p.remove) {
    s.fail("remove", "the same side cannot be both fixed and removed");
  }
  return p;
}

// Names within one rock mass must differ: they name the planes in messages and reports.
template <typename T>
void requireUniqueNames(const std::vector<Section>& sections, const std::vector<T>& items) {
  for (std::size_t i = 0; i < items.size(); ++i) {
    for (std::size_t j = 0; j < i; ++j) {
      if (items[i].name == items[j].name) {
        sections[i].fail("name",
                         cat("'", items[i].name, "' is already used at line ", sections[j].line()));
      }
    }
  }
}

// The [[joint]] of every plane of `mass` (-1: none): single planes first, in order, then the
// planes of the joint sets, each named "<set>#<k>" (geometry/rock_mass.h).
std::vector<int> planeJoints(const geometry::RockMass& mass, const std::vector<Section>& planes,
                             const std::vector<Section>& sets, const setup::Setup& scene) {
  std::vector<int> set_joint;
  for (const Section& j : sets) set_joint.push_back(jointReference(j, "joint", scene));
  std::vector<int> out;
  for (std::size_t k = 0; k < mass.planes.size(); ++k) {
    if (k < planes.size()) {
      out.push_back(jointReference(planes[k], "joint", scene));
      continue;
    }
    const std::string& name = mass.plane_names[k];
    const std::string set = name.substr(0, name.rfind('#'));
    int joint = -1;
    for (std::size_t j = 0; j < sets.size(); ++j) {
      if (sets[j].string("name") == set) joint = set_joint[j];
    }
    out.push_back(joint);
  }
  return out;
}

std::string sliverText(const geometry::RockMassReport& r) {
  const std::size_t kept = r.kept_slivers.size();
  if (r.slivers_merged + r.slivers_dropped == 0 && kept == 0) return "no slivers";
  return cat(r.slivers_merged, " sliver(s) merged, ", kept > 0 ? cat(kept, " kept, ") : "",
             r.slivers_dropped, " dropped (", num(r.dropped_volume), " m^3)");
}

// One warning for each piece (the first few, then a count): where it is and how big.
void warnPieces(const Section& s, const std::vector<geometry::RockPiece>& pieces,
                const std::string& what, const std::string& why) {
  constexpr std::size_t kListed = 10;
  for (std::size_t i = 0; i < pieces.size() && i < kListed; ++i) {
    const geometry::RockPiece& p = pieces[i];
    log::warning(cat(s.context().file(), ":", s.line(), ": ", s.name(), ": ", what, " of ",
                     num(p.volume), " m^3 at (", num(p.centroid.x()), ", ", num(p.centroid.y()),
                     ", ", num(p.centroid.z()), ")", why));
  }
  if (pieces.size() > kListed) {
    log::warning(cat(s.context().file(), ":", s.line(), ": ", s.name(), ": and ",
                     pieces.size() - kListed, " more like it"));
  }
}

// Each joint set's planes checked at its own line (spacing, origin), before the whole mass.
void checkJointSets(const std::vector<Section>& sections, const geometry::RockMassSpec& spec) {
  const std::vector<Vec3> corners = spec.region.corners();
  for (std::size_t i = 0; i < sections.size(); ++i) {
    try {
      geometry::jointSetPlanes(spec.joint_sets[i], corners);
    } catch (const GeometryError& e) {
      std::string message = e.what();  // without "joint set 'J1': ": the section names it
      const std::string named = cat("joint set '", spec.joint_sets[i].name, "': ");
      if (message.starts_with(named)) message.erase(0, named.size());
      sections[i].failHere(message);
    }
  }
}

// Cuts, with a progress line every few seconds; a stop signal ends it with this file and line.
geometry::RockMass cut(const Section& s, geometry::RockMassSpec& spec) {
  const std::string where = cat(s.context().file(), ":", s.line(), ": ", s.name());
  spec.progress = [&where](const geometry::CutProgress& p) {
    log::info(cat(where, ": cutting, plane ", p.planes_done, " of ", p.planes, ", ", p.blocks,
                  " blocks so far (", num(p.seconds), " s)"));
  };
  try {
    return geometry::cutRockMass(spec);
  } catch (const GeometryError& e) {
    s.failHere(std::string("cannot cut the rock mass: ") + e.what());
  } catch (const Interrupted& e) {
    throw Interrupted(cat(where, ": ", e.what()));
  } catch (const std::bad_alloc&) {
    s.failHere("ran out of memory cutting the rock mass: increase the joint sets' spacings");
  }
}

}  // namespace

std::vector<setup::FacePlane> blockFacePlanes(const geometry::RockMass& mass,
                                              const geometry::RockBlock& block, int first_plane) {
  // A plane with three of the block's corners on it holds a face of the block (three corners of
  // a convex polyhedron are never in a line). The corners were computed on the planes that cut
  // them, to round-off relative to their coordinates.
  double reach = 0.0;
  for (const Vec3& v : block.vertices) reach = std::max(reach, v.cwiseAbs().maxCoeff());
  const double tolerance = 1e-9 * reach;
  std::vector<setup::FacePlane> out;
  for (std::size_t k = 0; k < mass.planes.size(); ++k) {
    const geometry::Plane& p = mass.planes[k];
    int on = 0;
    for (const Vec3& v : block.vertices) on += std::abs(p.normal.dot(v) - p.offset) <= tolerance;
    if (on >= 3) out.push_back({p.normal, p.offset, first_plane + static_cast<int>(k)});
  }
  return out;
}

RockMassCut readRockMass(const Section& s, const setup::Setup& scene) {
  s.allowOnly({"name", "material", "fixed_material", "label_prefix", "min_volume", "min_thickness",
               "slivers", "joints_cut_fixed", "max_blocks", "region", "joint_set", "plane"});
  RockMassCut out;
  out.info.name = s.requiredString("name");
  out.info.line = s.line();
  out.info.label_prefix = s.string("label_prefix").value_or(out.info.name);
  const auto material = [&](std::string_view key, const std::string& name) {
    const int index = indexByName(scene.materials, name);
    if (index < 0) s.fail(key, "no [[material]] is named '" + name + "'");
    return index;
  };
  out.material = material("material", s.requiredString("material"));
  out.fixed_material = s.has("fixed_material")
                           ? material("fixed_material", *s.string("fixed_material"))
                           : out.material;

  geometry::RockMassSpec spec;
  spec.region = readRegion(s);
  spec.min_volume = s.number("min_volume", Quantity::kVolume, 0.0, Range::kNonNegative);
  spec.min_thickness = s.number("min_thickness", Quantity::kLength, 0.0, Range::kNonNegative);
  spec.slivers = s.choice("slivers", {"merge", "drop"}, "merge") == "merge"
                     ? geometry::Slivers::kMerge
                     : geometry::Slivers::kDrop;
  spec.joints_cut_fixed = s.boolean("joints_cut_fixed").value_or(false);
  spec.max_blocks =
      s.number("max_blocks", Quantity::kDimensionless, geometry::kMaxRockBlocks, Range::kPositive);
  const std::vector<Section> sets = nestedEntries(s, "joint_set", "[[joint_set]]");
  for (const Section& j : sets) spec.joint_sets.push_back(readJointSet(j));
  requireUniqueNames(sets, spec.joint_sets);
  const std::vector<Section> planes = nestedEntries(s, "plane", "[[plane]]");
  for (const Section& p : planes) spec.planes.push_back(readPlane(p));
  requireUniqueNames(planes, spec.planes);

  checkJointSets(sets, spec);
  out.mass = cut(s, spec);
  out.plane_joint = planeJoints(out.mass, planes, sets, scene);
  const geometry::RockMassReport& r = out.mass.report;
  if (out.mass.blocks.empty()) s.failHere("no block is left (every block was removed)");
  warnPieces(s, r.dropped, "dropped a sliver", " (slivers = \"drop\")");
  warnPieces(s, r.kept_slivers, "kept a sliver",
             " as a block of its own: no neighbour can take it in and stay convex");
  if (r.free_blocks == 0)
    log::warning(cat(s.context().file(), ":", s.line(), ": ", s.name(), ": every block is fixed"));
  out.info.plane_names = out.mass.plane_names;
  out.info.report = r;
  log::info(cat(s.context().file(), ":", s.line(), ": ", s.name(), ": ", r.free_blocks,
                " free and ", r.fixed_blocks, " fixed blocks from ", r.planes, " planes; ",
                sliverText(r), "; smallest block ", num(r.smallest_volume), " m^3, ",
                num(r.smallest_thickness), " m thick",
                r.removed_blocks > 0 ? cat("; ", r.removed_blocks, " removed") : std::string()));
  return out;
}

}  // namespace polydem::scene::detail
