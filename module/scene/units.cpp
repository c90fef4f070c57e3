#include "polydem/scene/units.h"

#include <charconv>
#include <cmath>
#include <stdexcept>

#include "polydem/core/types.h"

namespace polydem::scene {

namespace {

struct Symbol {
  std::string_view name;
  Dimension dimension;
  int pow10;      // the unit is factor * 10^pow10 SI units
  double factor;  // non-decimal part (minutes, hours)
  int deg, rad;   // angular part
  bool prefixable;
};

// clang-format off
constexpr Symbol kSymbols[] = {
    {"m",   {0, 1, 0, 0},   0, 1.0,    0, 0, true},
    {"g",   {1, 0, 0, 0},  -3, 1.0,    0, 0, true},
    {"s",   {0, 0, 1, 0},   0, 1.0,    0, 0, true},
    {"N",   {1, 1, -2, 0},  0, 1.0,    0, 0, true},
    {"Pa",  {1, -1, -2, 0}, 0, 1.0,    0, 0, true},
    {"Hz",  {0, 0, -1, 0},  0, 1.0,    0, 0, true},
    {"rad", {0, 0, 0, 1},   0, 1.0,    0, 1, true},
    {"deg", {0, 0, 0, 1},   0, 1.0,    1, 0, false},
    {"min", {0, 0, 1, 0},   0, 60.0,   0, 0, false},
    {"h",   {0, 0, 1, 0},   0, 3600.0, 0, 0, false},
};
// clang-format on

struct Prefix {
  std::string_view name;
  int pow10;
};
constexpr Prefix kPrefixes[] = {{"G", 9},  {"M", 6},  {"k", 3},       {"c", -2},
                                {"m", -3}, {"u", -6}, {"\u00b5", -6}, {"n", -9}};

// A symbol with its prefix resolved; the whole name is tried first, so "min" is minutes and "mm"
// is millimetres.
const Symbol* findSymbol(std::string_view name, int& prefix_pow10) {
  prefix_pow10 = 0;
  for (const Symbol& s : kSymbols) {
    if (s.name == name) return &s;
  }
  for (const Prefix& p : kPrefixes) {
    if (name.size() <= p.name.size() || name.substr(0, p.name.size()) != p.name) continue;
    for (const Symbol& s : kSymbols) {
      if (s.prefixable && s.name == name.substr(p.name.size())) {
        prefix_pow10 = p.pow10;
        return &s;
      }
    }
  }
  return nullptr;
}

bool isSpace(char c) {
  return c == ' ' || c == '\t';
}
bool isSymbolChar(char c) {
  return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || static_cast<unsigned char>(c) >= 0x80;
}

Dimension scaled(const Dimension& d, int k) {
  return {d.mass * k, d.length * k, d.time * k, d.angle * k};
}
Dimension sum(const Dimension& a, const Dimension& b) {
  return {a.mass + b.mass, a.length + b.length, a.time + b.time, a.angle + b.angle};
}

// 10^p for |p| <= 22 is exact in double; applying it once (multiplying or dividing) keeps
// "1 mm" == 1e-3 and "1.5 g/cm^3" == 1500 exact.
double applyPow10(double v, int p) {
  double scale = 1.0;
  for (int i = 0; i < std::abs(p); ++i) scale *= 10.0;
  return p >= 0 ? v * scale : v / scale;
}

[[noreturn]] void bad(const std::string& why) {
  throw std::invalid_argument(why);
}

}  // namespace

Dimension dimensionOf(Quantity q) {
  switch (q) {
    case Quantity::kDimensionless:
      return {};
    case Quantity::kLength:
      return {0, 1, 0, 0};
    case Quantity::kVolume:
      return {0, 3, 0, 0};
    case Quantity::kTime:
      return {0, 0, 1, 0};
    case Quantity::kVelocity:
      return {0, 1, -1, 0};
    case Quantity::kAcceleration:
      return {0, 1, -2, 0};
    case Quantity::kDensity:
      return {1, -3, 0, 0};
    case Quantity::kStiffness:
      return {1, 0, -2, 0};
    case Quantity::kPressure:
      return {1, -1, -2, 0};
    case Quantity::kJointStiffness:
      return {1, -2, -2, 0};
    case Quantity::kForce:
      return {1, 1, -2, 0};
    case Quantity::kAngle:
    case Quantity::kPhase:
      return {0, 0, 0, 1};
    case Quantity::kAngularVelocity:
      return {0, 0, -1, 1};
    case Quantity::kFrequency:
      return {0, 0, -1, 0};
    case Quantity::kUnitWeight:
      return {1, -2, -2, 0};
  }
  return {};
}

std::string storedUnit(Quantity q) {
  switch (q) {
    case Quantity::kDimensionless:
      return "1";
    case Quantity::kLength:
      return "m";
    case Quantity::kVolume:
      return "m^3";
    case Quantity::kTime:
      return "s";
    case Quantity::kVelocity:
      return "m/s";
    case Quantity::kAcceleration:
      return "m/s^2";
    case Quantity::kDensity:
      return "kg/m^3";
    case Quantity::kStiffness:
      return "N/m";
    case Quantity::kPressure:
      return "Pa";
    case Quantity::kJointStiffness:
      return "Pa/m";
    case Quantity::kForce:
      return "N";
    case Quantity::kAngle:
      return "deg";
    case Quantity::kPhase:
      return "rad";
    case Quantity::kAngularVelocity:
      return "rad/s";
    case Quantity::kFrequency:
      return "Hz";
    case Quantity::kUnitWeight:
      return "N/m^3";
  }
  return "1";
}

std::string describe(Quantity q) {
  switch (q) {
    case Quantity::kDimensionless:
      return "a dimensionless number";
    case Quantity::kLength:
      return "a length (m)";
    case Quantity::kVolume:
      return "a volume (m^3)";
    case Quantity::kTime:
      return "a time (s)";
    case Quantity::kVelocity:
      return "a velocity (m/s)";
    case Quantity::kAcceleration:
      return "an acceleration (m/s^2)";
    case Quantity::kDensity:
      return "a density (kg/m^3)";
    case Quantity::kStiffness:
      return "a stiffness (N/m)";
    case Quantity::kPressure:
      return "a pressure (Pa)";
    case Quantity::kJointStiffness:
      return "a stiffness per area (Pa/m)";
    case Quantity::kForce:
      return "a force (N)";
    case Quantity::kAngle:
      return "an angle (deg or rad; plain numbers are degrees)";
    case Quantity::kPhase:
      return "an angle (rad or deg; plain numbers are radians)";
    case Quantity::kAngularVelocity:
      return "an angular velocity (rad/s or deg/s; plain numbers are rad/s)";
    case Quantity::kFrequency:
      return "a frequency (Hz)";
    case Quantity::kUnitWeight:
      return "a unit weight (N/m^3)";
  }
  return {};
}

std::string toString(const Dimension& d) {
  if (d.dimensionless()) return "dimensionless";
  std::string out;
  auto term = [&out](const char* name, int power) {
    if (power == 0) return;
    if (!out.empty()) out += ' ';
    out += name;
    if (power != 1) out += '^' + std::to_string(power);
  };
  term("kg", d.mass);
  term("m", d.length);
  term("s", d.time);
  term("rad", d.angle);
  return out;
}

std::string describe(const Dimension& d) {
  if (d == Dimension{0, 0, 0, 1}) return "an angle";
  if (d == dimensionOf(Quantity::kAngularVelocity)) return "an angular velocity";
  for (Quantity q :
       {Quantity::kDimensionless, Quantity::kLength, Quantity::kVolume, Quantity::kTime,
        Quantity::kVelocity, Quantity::kAcceleration, Quantity::kDensity, Quantity::kStiffness,
        Quantity::kPressure, Quantity::kJointStiffness, Quantity::kForce, Quantity::kFrequency}) {
    if (dimensionOf(q) == d) return describe(q);
  }
  return toString(d);
}

ParsedQuantity parseQuantity(std::string_view text) {
  std::size_t i = 0;
  while (i < text.size() && isSpace(text[i])) ++i;
  if (i < text.size() && text[i] == '+') ++i;  // from_chars takes '-' but not '+'
  double number = 0.0;
  const auto [end, ec] = std::from_chars(text.data() + i, text.data() + text.size(), number);
  if (ec != std::errc() || end == text.data() + i) bad("it does not start with a number");
  if (!std::isfinite(number)) bad("the number is not finite");
  if (i > 0 && text[i - 1] == '+' && number < 0) bad("two signs");
  i = static_cast<std::size_t>(end - text.data());

  ParsedQuantity out;
  int pow10 = 0;
  double factor = 1.0;
  bool divide = false, expect_symbol = false;
  while (true) {
    while (i < text.size() && isSpace(text[i])) ++i;
    if (i == text.size()) break;
    const char c = text[i];
    if (c == '*' || c == '/') {
      if (expect_symbol || (c == '*' && !out.has_unit)) bad(std::string("misplaced '") + c + "'");
      divide = c == '/';
      expect_symbol = true;
      ++i;
      continue;
    }
    const std::size_t start = i;
    while (i < text.size() && isSymbolChar(text[i])) ++i;
    if (i == start) bad(std::string("unexpected '") + c + "' in the unit");
    const std::string_view name = text.substr(start, i - start);
    int power = 1;
    if (i < text.size() && text[i] == '^') {
      ++i;
      const auto [pend, pec] = std::from_chars(text.data() + i, text.data() + text.size(), power);
      if (pec != std::errc() || pend == text.data() + i)
        bad("a '^' must be followed by an integer");
      if (std::abs(power) > 9) bad("the power " + std::to_string(power) + " is out of range");
      i = static_cast<std::size_t>(pend - text.data());
    }
    if (divide) power = -power;
    out.has_unit = true;
    divide = expect_symbol = false;
    int prefix = 0;
    const Symbol* s = findSymbol(name, prefix);
    if (!s) bad("unknown unit '" + std::string(name) + "'");
    out.dimension = sum(out.dimension, scaled(s->dimension, power));
    pow10 += (s->pow10 + prefix) * power;
    factor *= std::pow(s->factor, power);
    out.deg_power += s->deg * power;
    out.rad_power += s->rad * power;
  }
  if (expect_symbol) bad("the unit ends with an operator");
  if (std::abs(pow10) > 22) bad("the unit's power of ten is out of range");
  out.value = applyPow10(number, pow10) * factor;
  if (!std::isfinite(out.value)) bad("the value overflows");
  return out;
}

double toStoredUnit(const ParsedQuantity& p, Quantity q) {
  // Convert each angular unit to the stored one; a power of zero leaves the value untouched.
  const bool degrees = q == Quantity::kAngle;
  const double deg = degrees ? 1.0 : kPi / 180.0;
  const double rad = degrees ? 180.0 / kPi : 1.0;
  double v = p.value;
  if (p.deg_power != 0) v *= std::pow(deg, p.deg_power);
  if (p.rad_power != 0) v *= std::pow(rad, p.rad_power);
  return v;
}

}  // namespace polydem::scene
