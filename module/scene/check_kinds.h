// The kinds of [[check]] and what each takes: the unit of its value (for `expected` and
// `tolerance`) and its parameters with their types and valid ranges. The scene reader accepts
// exactly these keys (a misspelt one is an error at its line, never a silent default) and checks
// every value where it reads it. Each kind is declared in its own file under check_kinds/ (named
// after it: check_kinds/free_motion.cpp declares "free_motion") and computed by the file of the
// same name under module/run/checks/, which reads only declared parameters. The table is
// check_kinds/check_table.cpp; docs/scene-format.md lists it.
#pragma once

#include <limits>
#include <string_view>
#include <vector>

#include "polydem/scene/units.h"
#include "polydem/setup/setup.h"

namespace polydem::scene {

enum class CheckParamType {
  kNumber,     // one number with the parameter's quantity and range
  kDirection,  // [x, y, z], not zero; stored normalised
  kParticles,  // "label" or "label1, label2, ...": labelled particles
  kParticle,   // exactly one label
  kWord,       // one of `words`
  kText,       // any non-empty text (a label prefix)
};

struct CheckParam {
  std::string_view name;
  CheckParamType type = CheckParamType::kNumber;
  bool required = false;
  Quantity quantity = Quantity::kDimensionless;          // kNumber: dimension and stored unit
  double lo = -std::numeric_limits<double>::infinity();  // kNumber: valid range, stored unit
  double hi = std::numeric_limits<double>::infinity();
  bool lo_open = false, hi_open = false;  // open ends exclude lo, hi
  std::vector<std::string_view> words;    // kWord
  std::string_view help;                  // one line, for docs and messages
  // kNumber: in the unit of what the check measures (free_motion's `limit`: that of its
  // `quantity`), not in `quantity`; see measuredQuantity().
  bool measured = false;
};

struct CheckKind {
  std::string_view name;
  Quantity value = Quantity::kDimensionless;  // the check's value: how expected/tolerance read
  std::string_view value_help;                // what the value is, with its unit
  std::vector<CheckParam> params;
};

/// The unit of what a check of `kind` measures: the kind's `value`, except for free_motion, whose
/// `quantity` word (already read into spec.strings) decides it.
Quantity measuredQuantity(const CheckKind& kind, const setup::CheckSpec& spec);
/// The unit of a check's value, in which `expected` and `tolerance` are read and reported:
/// measuredQuantity(), except for free_motion at = "first_below", whose value is a time.
Quantity valueQuantity(const CheckKind& kind, const setup::CheckSpec& spec);

/// Every kind, in the order of docs/scene-format.md.
const std::vector<CheckKind>& checkKinds();
/// The kind called `name`, or nullptr.
const CheckKind* findCheckKind(std::string_view name);
/// The parameter `name` of `kind`, or nullptr.
const CheckParam* findCheckParam(const CheckKind& kind, std::string_view name);
/// "displacement, rotation, ...": for messages.
std::string checkKindNames();

}  // namespace polydem::scene
