// Bindings of geometry/rock_mass.h: cut a rock mass from Python with the keys of a scene file's
// [[rock_mass]] (docs/scene-format.md), angles in degrees, lengths in metres.
#include <set>
#include <string>

#include "bindings.h"
#include "polydem/core/strings.h"
#include "polydem/geometry/rock_mass.h"

namespace polydem::python {

namespace {

using namespace geometry;

// A dict's keys, each taken at most once; keys nobody asked for are errors.
class Keys {
 public:
  Keys(const py::dict& d, std::string what, std::set<std::string> known)
      : d_(d), what_(std::move(what)) {
    for (const auto& item : d) {
      const std::string key = py::str(item.first);
      if (!known.count(key)) {
        throw py::value_error(
            cat(what_, ": unknown key '", key,
                "'; known: ", join(std::vector<std::string>(known.begin(), known.end()), ", ")));
      }
    }
  }
  bool has(const char* key) const { return d_.contains(key); }
  py::handle get(const char* key) const {
    if (!has(key)) throw py::value_error(cat(what_, ": missing key '", key, "'"));
    return d_[key];
  }
  double number(const char* key, std::optional<double> fallback = std::nullopt) const {
    if (!has(key) && fallback) return *fallback;
    try {
      return get(key).cast<double>();
    } catch (const py::cast_error&) {
      throw py::value_error(cat(what_, ": '", key, "' must be a number"));
    }
  }
  std::string text(const char* key, const std::string& fallback) const {
    return has(key) ? py::str(d_[key]).cast<std::string>() : fallback;
  }
  Vec3 vec3(const char* key, const Vec3& fallback) const {
    return has(key) ? toVec3(d_[key], cat(what_, " ", key).c_str()) : fallback;
  }
  const std::string& what() const { return what_; }

 private:
  const py::dict& d_;
  std::string what_;
};

RockRegion region(const py::dict& d) {
  const Keys k(d, "region", {"type", "min", "max", "vertices", "profile", "y"});
  const std::string type = k.text("type", "");
  if (type == "box") return boxRegion(k.vec3("min", Vec3::Zero()), k.vec3("max", Vec3::Zero()));
  if (type == "polyhedron") return polyhedronRegion(toPoints(k.get("vertices"), "vertices"));
  if (type == "profile") {
    const auto xz = py::cast<std::vector<std::pair<double, double>>>(k.get("profile"));
    std::vector<Vec2> profile;
    for (const auto& [x, z] : xz) profile.emplace_back(x, z);
    const auto y = py::cast<std::pair<double, double>>(k.get("y"));
    return profileRegion(profile, y.first, y.second);
  }
  throw py::value_error("region: 'type' must be 'box', 'polyhedron' or 'profile'");
}

Side side(const Keys& k, const char* key) {
  const std::string s = k.text(key, "none");
  if (s == "below") return Side::kBelow;
  if (s == "above") return Side::kAbove;
  if (s == "none") return Side::kNone;
  throw py::value_error(cat(k.what(), ": '", key, "' must be 'below', 'above' or 'none'"));
}

py::dict report(const RockMassReport& r) {
  py::dict d;
  d["region_volume"] = r.region_volume;
  d["planes"] = r.planes;
  d["free_blocks"] = r.free_blocks;
  d["fixed_blocks"] = r.fixed_blocks;
  d["removed_blocks"] = r.removed_blocks;
  d["removed_volume"] = r.removed_volume;
  d["slivers_merged"] = r.slivers_merged;
  d["slivers_dropped"] = r.slivers_dropped;
  d["dropped_volume"] = r.dropped_volume;
  d["smallest_volume"] = r.smallest_volume;
  d["smallest_thickness"] = r.smallest_thickness;
  return d;
}

py::dict cut(const py::dict& region_dict, const py::list& joint_sets, const py::list& planes,
             double min_volume, double min_thickness, const std::string& slivers,
             bool joints_cut_fixed, double max_blocks) {
  RockMassSpec spec;
  spec.region = region(region_dict);
  for (const auto& item : joint_sets) {
    const py::dict d = item.cast<py::dict>();
    const Keys k(d, "joint set",
                 {"name", "dip", "dip_direction", "spacing", "offset", "origin", "spacing_jitter",
                  "orientation_jitter", "seed"});
    JointSet j;
    j.name = k.text("name", cat("set", spec.joint_sets.size() + 1));
    j.dip = k.number("dip");
    j.dip_direction = k.number("dip_direction");
    j.spacing = k.number("spacing");
    j.offset = k.number("offset", 0.0);
    j.origin = k.vec3("origin", Vec3::Zero());
    j.spacing_jitter = k.number("spacing_jitter", 0.0);
    j.orientation_jitter = k.number("orientation_jitter", 0.0);
    j.seed = static_cast<std::uint64_t>(k.number("seed", 0.0));
    spec.joint_sets.push_back(j);
  }
  for (const auto& item : planes) {
    const py::dict d = item.cast<py::dict>();
    const Keys k(d, "plane", {"name", "dip", "dip_direction", "point", "fixed", "remove"});
    SinglePlane p;
    p.name = k.text("name", cat("plane", spec.planes.size() + 1));
    p.plane.normal = normalFromDip(k.number("dip"), k.number("dip_direction"));
    p.plane.offset = p.plane.normal.dot(toVec3(k.get("point"), "plane point"));
    p.fixed = side(k, "fixed");
    p.remove = side(k, "remove");
    spec.planes.push_back(p);
  }
  spec.min_volume = min_volume;
  spec.min_thickness = min_thickness;
  if (slivers != "merge" && slivers != "drop") {
    throw py::value_error("slivers must be 'merge' or 'drop'");
  }
  spec.slivers = slivers == "merge" ? Slivers::kMerge : Slivers::kDrop;
  spec.joints_cut_fixed = joints_cut_fixed;
  if (!(max_blocks > 0.0)) throw py::value_error("max_blocks must be positive");
  spec.max_blocks = max_blocks;
  const RockMass mass = cutRockMass(spec);

  py::list vertices;
  const auto n = static_cast<py::ssize_t>(mass.blocks.size());
  const auto m = static_cast<py::ssize_t>(mass.planes.size());
  auto volume = emptyArray<double>({n});
  auto centroid = emptyArray<double>({n, 3});
  auto fixed = emptyArray<bool>({n});
  auto sides = emptyArray<std::int8_t>({n, m});
  for (py::ssize_t i = 0; i < n; ++i) {
    const RockBlock& b = mass.blocks[i];
    vertices.append(pointsArray(b.vertices));
    volume.mutable_data()[i] = b.volume;
    for (int c = 0; c < 3; ++c) centroid.mutable_data()[3 * i + c] = b.centroid[c];
    fixed.mutable_data()[i] = b.fixed;
    // The planes it touches are listed; of every other it lies wholly on one side.
    std::int8_t* row = sides.mutable_data() + i * m;
    for (py::ssize_t k = 0; k < m; ++k) row[k] = sideOf(b.vertices, mass.planes[k]);
    for (const PlaneSide& s : b.sides) row[s.plane] = s.side;
  }
  py::dict d;
  d["vertices"] = vertices;
  d["volume"] = volume;
  d["centroid"] = centroid;
  d["fixed"] = fixed;
  d["sides"] = sides;
  d["plane_names"] = mass.plane_names;
  d["report"] = report(mass.report);
  return d;
}

}  // namespace

py::dict rockMassReport(const RockMassReport& r) {
  return report(r);
}

void bindRockMass(py::module_& m) {
  m.def("cut_rock_mass", &cut, py::arg("region"), py::arg("joint_sets") = py::list(),
        py::arg("planes") = py::list(), py::arg("min_volume") = 0.0, py::arg("min_thickness") = 0.0,
        py::arg("slivers") = "merge", py::arg("joints_cut_fixed") = false,
        py::arg("max_blocks") = kMaxRockBlocks,
        R"(Cuts a rock mass into convex blocks, as a scene's [[rock_mass]] does.

`region`: {'type': 'box', 'min': [..], 'max': [..]}, {'type': 'polyhedron', 'vertices': (n, 3)}
or {'type': 'profile', 'profile': [(x, z), ...], 'y': (y_min, y_max)}. `joint_sets`: dicts with
name, dip, dip_direction (degrees; x east, y north, z up), spacing [m] and optionally offset [m],
origin, spacing_jitter (fraction), orientation_jitter [deg], seed. `planes`: dicts with name,
dip, dip_direction, point and optionally fixed / remove = 'below' | 'above'. Pieces below
`min_volume` [m^3] or thinner than `min_thickness` [m] (the diameter of the largest inscribed
sphere) are merged ('merge': the cut is not made there) or dropped ('drop').

Returns a dict: vertices (list of (k, 3) arrays), volume (n,), centroid (n, 3), fixed (n,) bool,
sides (n, planes) int8 (-1 below, +1 above, 0 across it uncut), plane_names, report (dict of counts and
volumes). The same description gives the same bits on every machine.)");
}

}  // namespace polydem::python
