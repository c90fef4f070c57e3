// [[random]] and [realizations]: a scene's random inputs and the scene files of its realizations
// (scene_random.h). Syntax in docs/scene-format.md, "Random inputs".
#include "polydem/scene/scene_random.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "polydem/core/error.h"
#include "polydem/core/logging.h"
#include "polydem/core/random.h"
#include "polydem/core/strings.h"
#include "polydem/geometry/joint_planes.h"
#include "polydem/scene/scene_reader.h"
#include "polydem/scene/toml_values.h"

namespace polydem::scene {

namespace {

using detail::Context;
using detail::Section;

const std::vector<std::string> kDistributions = {"normal", "lognormal", "uniform", "truncated",
                                                 "fisher"};

// Draw streams of one entry (uniformAt's `draw`); a joint set's seed is drawn apart.
constexpr std::uint64_t kValue = 0, kAzimuth = 1;
constexpr std::int64_t kJointSetSeeds = -1;

std::vector<std::string> splitPath(const std::string& path) {
  std::vector<std::string> out;
  std::size_t start = 0;
  for (std::size_t dot = path.find('.'); dot != std::string::npos; dot = path.find('.', start)) {
    out.push_back(path.substr(start, dot - start));
    start = dot + 1;
  }
  out.push_back(path.substr(start));
  return out;
}

// Whether an entry of an array of tables is the one `name` names: by its name or label, or for
// an [[interaction]] by its two materials, "a/b" in either order.
bool entryNamed(const toml::table& t, const std::string& name) {
  for (const char* key : {"name", "label"}) {
    if (const auto* v = t.get_as<std::string>(key); v && v->get() == name) return true;
  }
  const auto* m = t.get_as<toml::array>("materials");
  if (m && m->size() == 2 && (*m)[0].is_string() && (*m)[1].is_string()) {
    const std::string a = *(*m)[0].value<std::string>(), b = *(*m)[1].value<std::string>();
    return name == a + "/" + b || name == b + "/" + a;
  }
  return false;
}

// The table that holds the last key of `path` (nullptr with `problem` set when there is none).
// A table of the file is named by its key, an entry of an array of tables by its name.
toml::table* holder(toml::table& root, const std::vector<std::string>& path, std::string& problem) {
  toml::table* t = &root;
  std::string walked;
  for (std::size_t i = 0; i + 1 < path.size(); ++i) {
    const std::string& key = path[i];
    toml::node* n = t->get(key);
    walked += (walked.empty() ? "" : ".") + key;
    if (!n) {
      problem = cat("the scene has no '", walked, "'");
      return nullptr;
    }
    if (n->is_table()) {
      t = n->as_table();
      continue;
    }
    toml::array* a = n->as_array();
    if (!a || !a->is_array_of_tables()) {
      problem = cat("'", walked, "' is not a table");
      return nullptr;
    }
    if (i + 2 >= path.size()) {
      problem = cat("'", walked, "' is a list of [[", key, "]] entries: name one, as in '", walked,
                    ".NAME.", path.back(), "'");
      return nullptr;
    }
    const std::string& name = path[++i];
    toml::table* found = nullptr;
    for (auto& e : *a) {
      if (entryNamed(*e.as_table(), name)) found = e.as_table();
    }
    if (!found) {
      problem = cat("no [[", walked, "]] entry is named '", name, "'");
      return nullptr;
    }
    walked += "." + name;
    t = found;
  }
  return t;
}

Section entrySection(const Context& ctx, const toml::table& t, std::size_t i) {
  const auto* p = t.get_as<std::string>("parameter");
  return Section(ctx, t, cat("[[random]] ", p ? "'" + p->get() + "'" : cat("#", i + 1)));
}

RandomInput readInput(const Section& s) {
  s.allowOnly({"parameter", "distribution", "mean", "sd", "min", "max", "k"});
  RandomInput in;
  in.line = s.line();
  in.parameter = s.requiredString("parameter");
  if (in.parameter.empty()) s.fail("parameter", "is empty");
  if (!s.has("distribution")) s.missing("distribution");
  in.distribution = s.choice("distribution", kDistributions, "");
  const auto required = [&s](std::string_view key) {
    return s.requiredNumber(key, Quantity::kDimensionless);
  };
  const std::string& d = in.distribution;
  const bool has_mean = d == "normal" || d == "lognormal" || d == "truncated";
  const bool has_bounds = d == "uniform" || d == "truncated";
  for (const char* key : {"mean", "sd"}) {
    if (!has_mean && s.has(key)) s.fail(key, cat("is not a parameter of the ", d, " distribution"));
  }
  for (const char* key : {"min", "max"}) {
    if (!has_bounds && s.has(key)) {
      s.fail(key, cat("is not a parameter of the ", d, " distribution"));
    }
  }
  if (d != "fisher" && s.has("k")) s.fail("k", "is the concentration of the fisher distribution");
  if (has_mean) {
    in.mean = required("mean");
    in.sd = required("sd");
    if (!(in.sd > 0.0)) s.fail("sd", cat("must be > 0, got ", in.sd));
    if (d == "lognormal" && !(in.mean > 0.0)) {
      s.fail("mean", cat("a lognormal value is positive: its mean must be > 0, got ", in.mean));
    }
  }
  if (has_bounds) {
    in.min = required("min");
    in.max = required("max");
    if (!(in.max > in.min)) s.fail("max", cat("must exceed min (", in.min, "), got ", in.max));
  }
  if (d == "fisher") {
    in.k = required("k");
    if (!(in.k > 0.0) || !std::isfinite(in.k)) s.fail("k", cat("must be > 0, got ", in.k));
  }
  return in;
}

// The file's value at `key` of `t` as a number (degrees for an angle), for a fisher entry's mean
// pole.
double angleOf(const Context& ctx, const toml::table& t, std::string_view key,
               const RandomInput& in) {
  const toml::node* n = t.get(key);
  if (!n) ctx.fail(in.line, cat("[[random]] '", in.parameter, "': it has no ", key));
  return detail::toNumber(ctx, *n, cat(in.parameter, ".", key), Quantity::kAngle);
}

// Checks that the entry's parameter names a value the file can take: a number (or a number with
// its unit), or a key its table does not give yet; for fisher, a table with dip and
// dip_direction.
void checkParameter(const Context& ctx, toml::table& root, const RandomInput& in) {
  const std::vector<std::string> path = splitPath(in.parameter);
  std::string problem;
  if (in.distribution == "fisher") {
    std::vector<std::string> whole = path;
    whole.push_back("dip");
    toml::table* t = holder(root, whole, problem);
    if (!t) ctx.fail(in.line, cat("[[random]] parameter '", in.parameter, "': ", problem));
    angleOf(ctx, *t, "dip", in);
    angleOf(ctx, *t, "dip_direction", in);
    return;
  }
  toml::table* t = holder(root, path, problem);
  if (!t) ctx.fail(in.line, cat("[[random]] parameter '", in.parameter, "': ", problem));
  const toml::node* v = t->get(path.back());
  if (v && !v->is_number() && !v->is_string()) {
    ctx.fail(in.line, cat("[[random]] parameter '", in.parameter, "': the scene gives ",
                          detail::typeName(*v), ", not one number"));
  }
}

std::uint64_t realizationSeed(std::uint64_t study_seed, std::int64_t index) {
  return splitMix64(study_seed ^ splitMix64(static_cast<std::uint64_t>(index)));
}

double uniformOpen(std::uint64_t seed, std::int64_t k, std::uint64_t draw) {
  // In (0, 1): the quantiles of unbounded distributions stay finite.
  return (std::floor(uniformAt(seed, k, draw) * 0x1.0p52) + 0.5) * 0x1.0p-52;
}

// A value of entry `in` from the uniform `u` in (0, 1), by the inverse of its distribution.
double drawValue(const RandomInput& in, double u) {
  const std::string& d = in.distribution;
  if (d == "normal") return in.mean + in.sd * normalQuantile(u);
  if (d == "lognormal") {
    // mean and sd are the value's: sigma^2 = ln(1 + (sd/mean)^2), mu = ln(mean) - sigma^2 / 2.
    const double s2 = std::log1p((in.sd / in.mean) * (in.sd / in.mean));
    return std::exp(std::log(in.mean) - 0.5 * s2 + std::sqrt(s2) * normalQuantile(u));
  }
  if (d == "uniform") return in.min + (in.max - in.min) * u;
  // truncated: the normal's quantile between Phi(a) and Phi(b).
  const double a = normalCdf((in.min - in.mean) / in.sd), b = normalCdf((in.max - in.mean) / in.sd);
  const double x = in.mean + in.sd * normalQuantile(a + (b - a) * u);
  return std::clamp(x, in.min, in.max);
}

// A fisher entry's draw: the pole (upward normal) turned from the file's by Fisher's angle about
// a uniform azimuth; returns (dip, dip_direction) in degrees.
std::pair<double, double> drawOrientation(double dip, double dip_direction, double k, double u,
                                          double v) {
  const Vec3 n0 = geometry::normalFromDip(dip, dip_direction);
  const double tilt = fisherAngle(k, u), azimuth = 2.0 * kPi * v;
  const Vec3 a = n0.unitOrthogonal(), b = n0.cross(a);
  Vec3 n = std::cos(tilt) * n0 + std::sin(tilt) * (std::cos(azimuth) * a + std::sin(azimuth) * b);
  if (n.z() < 0.0) n = -n;  // the same plane: joint poles are axial
  n.normalize();
  const double new_dip = radToDeg(std::acos(std::clamp(n.z(), -1.0, 1.0)));
  double direction = radToDeg(std::atan2(n.x(), n.y()));
  if (direction < 0.0) direction += 360.0;
  return {new_dip, direction};
}

// Every [[rock_mass.joint_set]] gets a seed of its own from the realization's.
void seedJointSets(toml::table& root, std::uint64_t seed) {
  toml::array* masses = root.get_as<toml::array>("rock_mass");
  if (!masses) return;
  std::int64_t count = 0;
  for (auto& m : *masses) {
    toml::table* mass = m.as_table();
    toml::array* sets = mass ? mass->get_as<toml::array>("joint_set") : nullptr;
    if (!sets) continue;
    for (auto& s : *sets) {
      if (toml::table* set = s.as_table()) {
        const double u = uniformAt(seed, kJointSetSeeds, static_cast<std::uint64_t>(count++));
        // A TOML integer is signed: 52 bits of the draw.
        set->insert_or_assign("seed", static_cast<std::int64_t>(u * 0x1.0p52));
      }
    }
  }
}

toml::table parseRoot(const Context& ctx, const std::string& text) {
  try {
    return toml::parse(text, ctx.file());
  } catch (const toml::parse_error& e) {
    ctx.fail(static_cast<int>(e.source().begin.line),
             cat("TOML syntax error at column ", e.source().begin.column, ": ", e.description()));
  }
}

// Realization `index` as a TOML table, its values drawn into `values`.
toml::table realizationTable(const Study& study, std::uint64_t seed, std::vector<double>& values) {
  const Context ctx(study.file);
  toml::table root = parseRoot(ctx, study.text);
  root.erase("random");
  root.erase("realizations");
  for (std::size_t k = 0; k < study.inputs.size(); ++k) {
    const RandomInput& in = study.inputs[k];
    const auto i = static_cast<std::int64_t>(k);
    std::vector<std::string> path = splitPath(in.parameter);
    std::string problem;
    if (in.distribution == "fisher") {
      path.push_back("dip");
      toml::table* t = holder(root, path, problem);
      const auto [dip, direction] =
          drawOrientation(angleOf(ctx, *t, "dip", in), angleOf(ctx, *t, "dip_direction", in), in.k,
                          uniformOpen(seed, i, kValue), uniformAt(seed, i, kAzimuth));
      t->insert_or_assign("dip", dip);
      t->insert_or_assign("dip_direction", direction);
      values.insert(values.end(), {dip, direction});
      continue;
    }
    toml::table* t = holder(root, path, problem);
    const double x = drawValue(in, uniformOpen(seed, i, kValue));
    t->insert_or_assign(path.back(), x);
    values.push_back(x);
  }
  seedJointSets(root, seed);
  return root;
}

}  // namespace

std::vector<std::string> Study::columns() const {
  std::vector<std::string> out;
  for (const RandomInput& in : inputs) {
    if (in.distribution == "fisher") {
      out.push_back(in.parameter + ".dip");
      out.push_back(in.parameter + ".dip_direction");
    } else {
      out.push_back(in.parameter);
    }
  }
  return out;
}

Study readStudy(const std::string& path) {
  Study study;
  study.file = path;
  study.text = readSceneText(path);
  const Context ctx(path);
  toml::table root = parseRoot(ctx, study.text);
  if (const toml::node* r = root.get("realizations")) {
    if (!r->is_table()) ctx.fail(detail::lineOf(*r), "[realizations] must be a table");
    const Section s(ctx, *r->as_table(), "[realizations]");
    s.allowOnly({"seed"});
    study.seed = static_cast<std::uint64_t>(s.integer("seed", 1, detail::Range::kNonNegative));
  }
  const toml::node* list = root.get("random");
  if (list && (!list->is_array() || !list->as_array()->is_array_of_tables())) {
    ctx.fail(detail::lineOf(*list), "random must be an array of tables: write [[random]] sections");
  }
  if (list) {
    const toml::array& a = *list->as_array();
    for (std::size_t i = 0; i < a.size(); ++i) {
      const Section s = entrySection(ctx, *a[i].as_table(), i);
      RandomInput in = readInput(s);
      for (const RandomInput& other : study.inputs) {
        if (other.parameter == in.parameter) {
          s.fail("parameter", cat("is already drawn at line ", other.line));
        }
      }
      checkParameter(ctx, root, in);
      study.inputs.push_back(in);
    }
  }
  if (study.inputs.empty()) {
    ctx.fail(0, "no [[random]] entry: a study of realizations needs at least one random input");
  }
  // Each value at its distribution's centre (the file's own orientation for fisher) must give a
  // scene that reads: a key the table does not take is reported at its entry's line.
  for (std::size_t k = 0; k < study.inputs.size(); ++k) {
    const RandomInput& in = study.inputs[k];
    if (in.distribution == "fisher") continue;
    toml::table probe = parseRoot(ctx, study.text);
    probe.erase("random");
    probe.erase("realizations");
    std::string problem;
    const std::vector<std::string> p = splitPath(in.parameter);
    const double centre = in.distribution == "uniform"     ? 0.5 * (in.min + in.max)
                          : in.distribution == "truncated" ? std::clamp(in.mean, in.min, in.max)
                                                           : in.mean;
    holder(probe, p, problem)->insert_or_assign(p.back(), centre);
    std::ostringstream text;
    text << probe;
    const log::Level level = log::level();
    log::setLevel(std::min(level, log::Level::kWarning));  // one block count, not one per entry
    try {
      parseScene(text.str(), "(the scene with this value)");
      log::setLevel(level);
    } catch (const InputError& e) {
      log::setLevel(level);
      ctx.fail(in.line, cat("[[random]] parameter '", in.parameter, "' at ", num(centre),
                            ": the scene does not take it: ", e.what()));
    }
  }
  return study;
}

Realization drawRealization(const Study& study, std::int64_t index) {
  Realization r;
  r.index = index;
  r.seed = realizationSeed(study.seed, index);
  const toml::table root = realizationTable(study, r.seed, r.values);
  std::ostringstream text;
  text << "# Realization " << index << " of " << study.file << " (seed " << study.seed
       << "): polydem fos --realizations wrote it; every [[random]] value is drawn.\n\n"
       << root << "\n";
  r.text = text.str();
  return r;
}

setup::Setup realizationScene(const Study& study, const Realization& r) {
  const std::string name = cat(study.file, " (realization ", r.index, ")");
  try {
    return parseScene(r.text, name);
  } catch (const InputError& e) {
    // Which draw the scene refused: the message names the key; point at the entries.
    std::string drawn;
    const std::vector<std::string> columns = study.columns();
    for (std::size_t k = 0; k < columns.size(); ++k) {
      drawn += cat(k ? ", " : "", columns[k], " = ", shortest(r.values[k]));
    }
    const int line = study.inputs.size() == 1 ? study.inputs.front().line : 0;
    throw InputError(study.file, line,
                     cat("realization ", r.index, " (", drawn, ") is not a valid scene: ", e.what(),
                         " (a distribution that reaches outside the value's range needs bounds: "
                         "use truncated)"));
  }
}

double normalCdf(double x) {
  return 0.5 * std::erfc(-x / std::sqrt(2.0));
}

double normalQuantile(double p) {
  if (!(p > 0.0 && p < 1.0)) {
    throw Error(cat("normal quantile: p = ", p, " is not in (0, 1)"));
  }
  // Acklam's rational approximation (relative error 1.15e-9) ...
  static constexpr double a[] = {-3.969683028665376e+01, 2.209460984245205e+02,
                                 -2.759285104469687e+02, 1.383577518672690e+02,
                                 -3.066479806614716e+01, 2.506628277459239e+00};
  static constexpr double b[] = {-5.447609879822406e+01, 1.615858368580409e+02,
                                 -1.556989798598866e+02, 6.680131188771972e+01,
                                 -1.328068155288572e+01};
  static constexpr double c[] = {-7.784894002430293e-03, -3.223964580411365e-01,
                                 -2.400758277161838e+00, -2.549732539343734e+00,
                                 4.374664141464968e+00,  2.938163982698783e+00};
  static constexpr double d[] = {7.784695709041462e-03, 3.224671290700398e-01,
                                 2.445134137142996e+00, 3.754408661907416e+00};
  constexpr double low = 0.02425;
  double x = 0.0;
  if (p < low || p > 1.0 - low) {
    const double q = std::sqrt(-2.0 * std::log(p < low ? p : 1.0 - p));
    x = (((((c[0] * q + c[1]) * q + c[2]) * q + c[3]) * q + c[4]) * q + c[5]) /
        ((((d[0] * q + d[1]) * q + d[2]) * q + d[3]) * q + 1.0);
    if (p > 1.0 - low) x = -x;
  } else {
    const double q = p - 0.5, r = q * q;
    x = (((((a[0] * r + a[1]) * r + a[2]) * r + a[3]) * r + a[4]) * r + a[5]) * q /
        (((((b[0] * r + b[1]) * r + b[2]) * r + b[3]) * r + b[4]) * r + 1.0);
  }
  // ... and one Halley step on Phi(x) - p to full double precision.
  const double e = normalCdf(x) - p;
  const double u = e * std::sqrt(2.0 * kPi) * std::exp(0.5 * x * x);
  return x - u / (1.0 + 0.5 * x * u);
}

}  // namespace polydem::scene
