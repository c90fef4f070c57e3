// Reading typed, dimensioned values out of toml++ tables, with every problem reported as an
// InputError carrying the file and line of the offending key or value. Internal to the scene
// reader.
#pragma once

#include <toml++/toml.h>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "polydem/core/types.h"
#include "polydem/scene/units.h"

namespace polydem::scene::detail {

/// Line of a node in the file; 0 if toml++ does not know it.
int lineOf(const toml::node& node);

/// "a string", "an array", ... for messages.
std::string typeName(const toml::node& node);

/// "what[i]": an element of an array, for messages.
std::string element(const std::string& what, std::size_t i);

/// The file being read: where errors point.
class Context {
 public:
  explicit Context(std::string file) : file_(std::move(file)) {}
  const std::string& file() const { return file_; }
  [[noreturn]] void fail(int line, const std::string& message) const;

 private:
  std::string file_;
};

/// Allowed values of a number.
enum class Range { kAny, kPositive, kNonNegative };

/// Conversions of single nodes; `what` names the value in messages ("[simulation] gravity[2]").
double toNumber(const Context& ctx, const toml::node& node, const std::string& what, Quantity q,
                Range range = Range::kAny);
Vec3 toVec3(const Context& ctx, const toml::node& node, const std::string& what, Quantity q,
            Range range = Range::kAny);
/// A rotation: one table (axis + angle, quaternion, or euler_zyx) or an array of them applied in
/// order.
Quat toRotation(const Context& ctx, const toml::node& node, const std::string& what);

/// One TOML table being read. Its name ("[simulation]", "[[material]] 'rock'") prefixes every
/// message about its keys.
class Section {
 public:
  Section(const Context& ctx, const toml::table& table, std::string name);

  const Context& context() const { return ctx_; }
  const toml::table& table() const { return table_; }
  const std::string& name() const { return name_; }
  int line() const;
  /// "[simulation] dt": a key of this table, for messages.
  std::string where(std::string_view key) const;

  /// Reports the key earliest in the file that is not in `known`.
  void allowOnly(const std::vector<std::string_view>& known) const;

  const toml::node* find(std::string_view key) const { return table_.get(key); }
  bool has(std::string_view key) const { return find(key) != nullptr; }
  /// Line of the key's value, or of the table when the key is absent.
  int lineOf(std::string_view key) const;
  [[noreturn]] void fail(std::string_view key, const std::string& message) const;
  [[noreturn]] void failHere(const std::string& message) const;
  [[noreturn]] void missing(std::string_view key) const;

  std::optional<double> number(std::string_view key, Quantity q, Range r = Range::kAny) const;
  double number(std::string_view key, Quantity q, double fallback, Range r = Range::kAny) const;
  double requiredNumber(std::string_view key, Quantity q, Range r = Range::kAny) const;
  /// A number that must lie in [lo, hi) (or [lo, hi] when `hi_inclusive`), in stored units.
  double bounded(std::string_view key, Quantity q, double fallback, double lo, double hi,
                 bool hi_inclusive) const;

  /// An integer; a float is accepted when it is a whole number (1e5).
  std::optional<std::int64_t> integer(std::string_view key, Range r = Range::kAny) const;
  std::int64_t integer(std::string_view key, std::int64_t fallback, Range r = Range::kAny) const;

  std::optional<Vec3> vec3(std::string_view key, Quantity q, Range r = Range::kAny) const;
  std::optional<std::array<std::int64_t, 3>> int3(std::string_view key, Range r) const;
  std::optional<std::array<bool, 3>> bool3(std::string_view key) const;

  std::optional<std::string> string(std::string_view key) const;
  std::string requiredString(std::string_view key) const;
  /// A string that must be one of `choices`.
  std::string choice(std::string_view key, const std::vector<std::string>& choices,
                     const std::string& fallback) const;
  std::optional<std::vector<std::string>> strings(std::string_view key) const;
  std::optional<bool> boolean(std::string_view key) const;
  std::optional<Quat> rotation(std::string_view key) const;

 private:
  const Context& ctx_;
  const toml::table& table_;
  std::string name_;
};

/// The entries of an array of tables at the top level ([[material]]), each as a Section named
/// "[[material]] 'name'" (or "#3" when the entry has no `name_key` string).
std::vector<Section> entries(const Context& ctx, const toml::table& root, std::string_view key,
                             std::string_view name_key);

}  // namespace polydem::scene::detail
