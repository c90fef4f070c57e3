// Physical quantities written with units in scene files: "1.5e8 N/m", "30 deg", "2500 kg/m^3".
//
// A unit expression is a product of symbols, each optionally raised to an integer power, joined by
// spaces or '*' and divided by '/' (which divides by the one symbol that follows it):
//   kg/m^3   m/s^2   N/m   kg m^-3   rad/s   /s
// Symbols: m g s N Pa Hz rad (all with the prefixes G M k c m u n), deg, min, h.
// Angles are a dimension of their own here (not dimensionless as in SI) so that "30 deg" given
// for a stiffness, or "2 rad" for a damping ratio, is caught.
#pragma once

#include <string>
#include <string_view>

namespace polydem::scene {

/// Exponents of the base dimensions: mass, length, time, angle.
struct Dimension {
  int mass = 0, length = 0, time = 0, angle = 0;
  bool operator==(const Dimension&) const = default;
  bool dimensionless() const { return *this == Dimension{}; }
};

/// What a scene-file key holds: its dimension, the unit a plain number is taken in, and the unit
/// the setup stores. Angles are stored in degrees, except angular velocities (rad/s) and phases
/// (rad), as setup/setup.h states field by field.
enum class Quantity {
  kDimensionless,
  kLength,
  kVolume,  // m^3
  kTime,
  kVelocity,
  kAcceleration,
  kDensity,
  kStiffness,        // N/m
  kPressure,         // Pa
  kJointStiffness,   // Pa/m: stiffness per area of a joint (3DEC's jkn, jks)
  kForce,            // N
  kAngle,            // stored in degrees; a plain number is degrees
  kPhase,            // stored in radians; a plain number is radians
  kAngularVelocity,  // stored in rad/s; a plain number is rad/s
  kFrequency,        // Hz
  kUnitWeight,       // N/m^3: weight per volume (water's gamma_w)
};

Dimension dimensionOf(Quantity q);
/// "a stiffness (N/m)": for messages.
std::string describe(Quantity q);
/// The unit a Quantity is stored in: "m", "m/s", "deg", "rad", "1" (dimensionless)...
std::string storedUnit(Quantity q);
/// "kg m^-1 s^-2" or "dimensionless": for messages.
std::string toString(const Dimension& d);
/// "a pressure (Pa)" when the dimension is one the reader knows, else toString(d).
std::string describe(const Dimension& d);

/// A number with a unit, as parsed. `value` is the number times the non-angular part of the unit
/// in SI; the angular part is kept as exponents of degrees and radians so that converting
/// "30 deg" to degrees is exact.
struct ParsedQuantity {
  double value = 0.0;
  Dimension dimension;  // angle = deg_power + rad_power
  int deg_power = 0, rad_power = 0;
  bool has_unit = false;  // false for a bare number written as a string ("1e-3")
};

/// Parses "<number> [unit]". Throws std::invalid_argument with a short reason ("unknown unit
/// 'kN/mm^'") on malformed input and for non-finite numbers.
ParsedQuantity parseQuantity(std::string_view text);

/// The parsed value in the unit `q` is stored in. The caller has checked the dimension.
double toStoredUnit(const ParsedQuantity& p, Quantity q);

}  // namespace polydem::scene
