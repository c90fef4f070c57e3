#include "polydem/scene/toml_values.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>

#include "polydem/core/error.h"
#include "polydem/core/strings.h"

namespace polydem::scene::detail {

namespace {

std::string show(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.10g", v);
  return buf;
}

// What the user wrote, for messages: the string itself, or the node's type.
std::string given(const toml::node& node) {
  if (const auto* s = node.as_string()) return "'" + s->get() + "'";
  if (const auto* i = node.as_integer()) return std::to_string(i->get());
  if (const auto* f = node.as_floating_point()) return show(f->get());
  if (const auto* b = node.as_boolean()) return b->get() ? "true" : "false";
  return typeName(node);
}

void checkRange(const Context& ctx, const toml::node& node, const std::string& what, double v,
                Range range) {
  // A subnormal number has lost precision and turns into infinities once divided by (an inverse
  // mass, a stiffness ratio): no physical input is that small.
  if (v != 0.0 && !std::isnormal(v)) {
    ctx.fail(lineOf(node), what + ": " + given(node) + " is below the smallest normal number (" +
                               show(std::numeric_limits<double>::min()) + "); write 0 or a " +
                               "larger value");
  }
  if (range == Range::kPositive && !(v > 0.0)) {
    ctx.fail(lineOf(node), what + ": must be > 0, got " + given(node));
  }
  if (range == Range::kNonNegative && !(v >= 0.0)) {
    ctx.fail(lineOf(node), what + ": must be >= 0, got " + given(node));
  }
}

// Levenshtein distance, for "did you mean" on unknown keys.
std::size_t editDistance(std::string_view a, std::string_view b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = up;
    }
  }
  return row[b.size()];
}

Quat singleRotation(const Context& ctx, const toml::table& table, const std::string& what) {
  const Section s(ctx, table, what);
  s.allowOnly({"axis", "angle", "quaternion", "euler_zyx"});
  const int forms = (s.has("axis") || s.has("angle")) + s.has("quaternion") + s.has("euler_zyx");
  if (forms != 1) {
    s.failHere("give exactly one of {axis, angle}, {quaternion} or {euler_zyx}");
  }
  if (s.has("quaternion")) {
    const toml::array* a = s.find("quaternion")->as_array();
    if (!a || a->size() != 4) {
      s.fail("quaternion", "expected 4 numbers [w, x, y, z], got " + given(*s.find("quaternion")));
    }
    double c[4];
    for (std::size_t i = 0; i < 4; ++i) {
      c[i] = toNumber(ctx, (*a)[i], element(s.where("quaternion"), i), Quantity::kDimensionless);
    }
    // Scaled by the largest component first: the norm of [1e308, 1e308, 0, 0] overflows.
    const double scale = std::max({std::abs(c[0]), std::abs(c[1]), std::abs(c[2]), std::abs(c[3])});
    if (!(scale > 0.0)) s.fail("quaternion", "must not be zero");
    return Quat(c[0] / scale, c[1] / scale, c[2] / scale, c[3] / scale).normalized();
  }
  if (s.has("euler_zyx")) {
    // Yaw about z, then pitch about the new y, then roll about the newest x (intrinsic z-y'-x'').
    const Vec3 e = *s.vec3("euler_zyx", Quantity::kAngle);
    return Quat(Eigen::AngleAxisd(degToRad(e[0]), Vec3::UnitZ()) *
                Eigen::AngleAxisd(degToRad(e[1]), Vec3::UnitY()) *
                Eigen::AngleAxisd(degToRad(e[2]), Vec3::UnitX()));
  }
  if (!s.has("axis")) s.missing("axis");
  const Vec3 axis = *s.vec3("axis", Quantity::kDimensionless);
  const double angle = s.requiredNumber("angle", Quantity::kAngle);
  const double scale = axis.cwiseAbs().maxCoeff();  // scaled first, as the quaternion above
  if (!(scale > 0.0)) s.fail("axis", "must not be zero");
  return Quat(Eigen::AngleAxisd(degToRad(angle), (axis / scale).normalized()));
}

}  // namespace

int lineOf(const toml::node& node) {
  return static_cast<int>(node.source().begin.line);
}

std::string typeName(const toml::node& node) {
  switch (node.type()) {
    case toml::node_type::table:
      return "a table";
    case toml::node_type::array:
      return "an array";
    case toml::node_type::string:
      return "a string";
    case toml::node_type::integer:
      return "an integer";
    case toml::node_type::floating_point:
      return "a float";
    case toml::node_type::boolean:
      return "a boolean";
    case toml::node_type::date:
    case toml::node_type::time:
    case toml::node_type::date_time:
      return "a date/time";
    case toml::node_type::none:
      break;
  }
  return "nothing";
}

std::string element(const std::string& what, std::size_t i) {
  return cat(what, "[", i, "]");
}

void Context::fail(int line, const std::string& message) const {
  throw InputError(file_, line, message);
}

double toNumber(const Context& ctx, const toml::node& node, const std::string& what, Quantity q,
                Range range) {
  double v = 0.0;
  if (const auto* i = node.as_integer()) {
    v = static_cast<double>(i->get());
  } else if (const auto* f = node.as_floating_point()) {
    v = f->get();
    if (!std::isfinite(v)) ctx.fail(lineOf(node), what + ": must be finite, got " + given(node));
  } else if (const auto* s = node.as_string()) {
    ParsedQuantity p;
    try {
      p = parseQuantity(s->get());
    } catch (const std::invalid_argument& e) {
      ctx.fail(lineOf(node), what + ": cannot read " + given(node) + " as " + describe(q) + " (" +
                                 e.what() + ")");
    }
    if (p.has_unit && p.dimension != dimensionOf(q)) {
      ctx.fail(lineOf(node), what + ": expected " + describe(q) + ", got " + given(node) +
                                 ", which is " + describe(p.dimension));
    }
    v = p.has_unit ? toStoredUnit(p, q) : p.value;
    if (!std::isfinite(v)) {
      ctx.fail(lineOf(node), what + ": " + given(node) + " overflows in " + describe(q));
    }
  } else {
    ctx.fail(lineOf(node), what + ": expected " + describe(q) + ", got " + typeName(node));
  }
  checkRange(ctx, node, what, v, range);
  return v;
}

Vec3 toVec3(const Context& ctx, const toml::node& node, const std::string& what, Quantity q,
            Range range) {
  const toml::array* a = node.as_array();
  if (!a || a->size() != 3) {
    ctx.fail(lineOf(node), what + ": expected an array of 3 values, each " + describe(q) +
                               ", got " +
                               (a ? "an array of " + std::to_string(a->size()) : given(node)));
  }
  Vec3 v;
  for (std::size_t i = 0; i < 3; ++i) {
    v[i] = toNumber(ctx, (*a)[i], element(what, i), q, range);
  }
  return v;
}

Quat toRotation(const Context& ctx, const toml::node& node, const std::string& what) {
  if (const toml::table* t = node.as_table()) return singleRotation(ctx, *t, what);
  const toml::array* a = node.as_array();
  if (!a || a->empty()) {
    ctx.fail(lineOf(node), what +
                               ": expected a rotation table ({axis, angle}, {quaternion} or "
                               "{euler_zyx}) or a non-empty array of them, got " +
                               given(node));
  }
  // Applied in order: the first rotation acts first, so it is the rightmost factor.
  Quat q = Quat::Identity();
  for (std::size_t i = 0; i < a->size(); ++i) {
    const std::string item = element(what, i);
    const toml::table* t = (*a)[i].as_table();
    if (!t) ctx.fail(lineOf((*a)[i]), item + ": expected a rotation table, got " + given((*a)[i]));
    q = singleRotation(ctx, *t, item) * q;
  }
  return q.normalized();
}

Section::Section(const Context& ctx, const toml::table& table, std::string name)
    : ctx_(ctx), table_(table), name_(std::move(name)) {}

int Section::line() const {
  return scene::detail::lineOf(table_);
}

std::string Section::where(std::string_view key) const {
  return name_ + " " + std::string(key);
}

void Section::allowOnly(const std::vector<std::string_view>& known) const {
  const toml::key* first = nullptr;
  for (auto&& [key, value] : table_) {
    if (std::find(known.begin(), known.end(), key.str()) != known.end()) continue;
    if (!first || key.source().begin.line < first->source().begin.line) first = &key;
  }
  if (!first) return;
  std::string message = name_ + ": unknown key '" + std::string(first->str()) + "'";
  std::string_view best;
  std::size_t best_distance = 3;  // suggest only close matches
  for (std::string_view k : known) {
    const std::size_t d = editDistance(first->str(), k);
    if (d < best_distance) best = k, best_distance = d;
  }
  if (!best.empty()) {
    message += " (did you mean '" + std::string(best) + "'?)";
  } else {
    message += " (known keys: " + join({known.begin(), known.end()}, ", ") + ")";
  }
  ctx_.fail(static_cast<int>(first->source().begin.line), message);
}

int Section::lineOf(std::string_view key) const {
  const toml::node* n = find(key);
  const int l = n ? scene::detail::lineOf(*n) : 0;
  return l > 0 ? l : line();
}

void Section::fail(std::string_view key, const std::string& message) const {
  ctx_.fail(lineOf(key), where(key) + ": " + message);
}

void Section::failHere(const std::string& message) const {
  ctx_.fail(line(), name_ + ": " + message);
}

void Section::missing(std::string_view key) const {
  ctx_.fail(line(), name_ + ": missing required key '" + std::string(key) + "'");
}

std::optional<double> Section::number(std::string_view key, Quantity q, Range r) const {
  const toml::node* n = find(key);
  if (!n) return std::nullopt;
  return toNumber(ctx_, *n, where(key), q, r);
}

double Section::number(std::string_view key, Quantity q, double fallback, Range r) const {
  return number(key, q, r).value_or(fallback);
}

double Section::requiredNumber(std::string_view key, Quantity q, Range r) const {
  if (!has(key)) missing(key);
  return *number(key, q, r);
}

double Section::bounded(std::string_view key, Quantity q, double fallback, double lo, double hi,
                        bool hi_inclusive) const {
  const std::optional<double> v = number(key, q);
  if (!v) return fallback;
  if (!(*v >= lo) || !(hi_inclusive ? *v <= hi : *v < hi)) {
    fail(key, "must lie in [" + show(lo) + ", " + show(hi) + (hi_inclusive ? "]" : ")") +
                  (q == Quantity::kAngle ? " degrees" : "") + ", got " + given(*find(key)));
  }
  return *v;
}

std::optional<std::int64_t> Section::integer(std::string_view key, Range r) const {
  const toml::node* n = find(key);
  if (!n) return std::nullopt;
  std::int64_t v = 0;
  if (const auto* i = n->as_integer()) {
    v = i->get();
  } else if (const auto* f = n->as_floating_point();
             f && std::isfinite(f->get()) && std::trunc(f->get()) == f->get() &&
             std::abs(f->get()) <= 9007199254740992.0) {  // 2^53: every such float is exact
    v = static_cast<std::int64_t>(f->get());
  } else {
    fail(key, "expected an integer, got " + given(*n));
  }
  checkRange(ctx_, *n, where(key), static_cast<double>(v), r);
  return v;
}

std::int64_t Section::integer(std::string_view key, std::int64_t fallback, Range r) const {
  return integer(key, r).value_or(fallback);
}

std::optional<Vec3> Section::vec3(std::string_view key, Quantity q, Range r) const {
  const toml::node* n = find(key);
  if (!n) return std::nullopt;
  return toVec3(ctx_, *n, where(key), q, r);
}

std::optional<std::array<std::int64_t, 3>> Section::int3(std::string_view key, Range r) const {
  const toml::node* n = find(key);
  if (!n) return std::nullopt;
  const toml::array* a = n->as_array();
  if (!a || a->size() != 3) fail(key, "expected an array of 3 integers, got " + given(*n));
  std::array<std::int64_t, 3> out{};
  for (std::size_t i = 0; i < 3; ++i) {
    const toml::node& e = (*a)[i];
    const std::string what = element(where(key), i);
    const auto* v = e.as_integer();
    if (!v) ctx_.fail(scene::detail::lineOf(e), what + ": expected an integer, got " + given(e));
    out[i] = v->get();
    checkRange(ctx_, e, what, static_cast<double>(out[i]), r);
  }
  return out;
}

std::optional<std::array<bool, 3>> Section::bool3(std::string_view key) const {
  const toml::node* n = find(key);
  if (!n) return std::nullopt;
  const toml::array* a = n->as_array();
  if (!a || a->size() != 3) fail(key, "expected an array of 3 booleans, got " + given(*n));
  std::array<bool, 3> out{};
  for (std::size_t i = 0; i < 3; ++i) {
    const auto* v = (*a)[i].as_boolean();
    if (!v) {
      ctx_.fail(scene::detail::lineOf((*a)[i]),
                element(where(key), i) + ": expected true or false, got " + given((*a)[i]));
    }
    out[i] = v->get();
  }
  return out;
}

std::optional<std::string> Section::string(std::string_view key) const {
  const toml::node* n = find(key);
  if (!n) return std::nullopt;
  const auto* s = n->as_string();
  if (!s) fail(key, "expected a string, got " + given(*n));
  return s->get();
}

std::string Section::requiredString(std::string_view key) const {
  if (!has(key)) missing(key);
  std::string s = *string(key);
  if (s.empty()) fail(key, "must not be empty");
  return s;
}

std::string Section::choice(std::string_view key, const std::vector<std::string>& choices,
                            const std::string& fallback) const {
  const std::optional<std::string> s = string(key);
  if (!s) return fallback;
  if (std::find(choices.begin(), choices.end(), *s) == choices.end()) {
    fail(key, "'" + *s + "' is not one of " + join(choices, ", "));
  }
  return *s;
}

std::optional<std::vector<std::string>> Section::strings(std::string_view key) const {
  const toml::node* n = find(key);
  if (!n) return std::nullopt;
  const toml::array* a = n->as_array();
  if (!a) fail(key, "expected an array of strings, got " + given(*n));
  std::vector<std::string> out;
  for (std::size_t i = 0; i < a->size(); ++i) {
    const auto* s = (*a)[i].as_string();
    if (!s) {
      ctx_.fail(scene::detail::lineOf((*a)[i]),
                element(where(key), i) + ": expected a string, got " + given((*a)[i]));
    }
    out.push_back(s->get());
  }
  return out;
}

std::optional<bool> Section::boolean(std::string_view key) const {
  const toml::node* n = find(key);
  if (!n) return std::nullopt;
  const auto* b = n->as_boolean();
  if (!b) fail(key, "expected true or false, got " + given(*n));
  return b->get();
}

std::optional<Quat> Section::rotation(std::string_view key) const {
  const toml::node* n = find(key);
  if (!n) return std::nullopt;
  return toRotation(ctx_, *n, where(key));
}

std::vector<Section> entries(const Context& ctx, const toml::table& root, std::string_view key,
                             std::string_view name_key) {
  std::vector<Section> out;
  const toml::node* n = root.get(key);
  if (!n) return out;
  const toml::array* a = n->as_array();
  if (!a || (!a->empty() && !a->is_array_of_tables())) {
    ctx.fail(lineOf(*n), "'" + std::string(key) + "' must be an array of tables: write [[" +
                             std::string(key) + "]] sections");
  }
  for (std::size_t i = 0; i < a->size(); ++i) {
    const toml::table& t = *(*a)[i].as_table();
    const toml::node* label = name_key.empty() ? nullptr : t.get(name_key);
    const bool named = label && label->is_string() && !label->as_string()->get().empty();
    out.emplace_back(ctx, t,
                     named ? cat("[[", key, "]] '", label->as_string()->get(), "'")
                           : cat("[[", key, "]] #", i + 1));
  }
  return out;
}

}  // namespace polydem::scene::detail
