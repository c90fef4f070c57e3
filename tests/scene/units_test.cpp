// The unit parser: SI prefixes, products, quotients, powers, angles, and its errors.
#include "polydem/scene/units.h"

#include <gtest/gtest.h>

#include <stdexcept>

#include "polydem/core/types.h"

namespace polydem::scene {
namespace {

double stored(std::string_view text, Quantity q) {
  const ParsedQuantity p = parseQuantity(text);
  EXPECT_EQ(p.dimension, dimensionOf(q)) << text;
  return toStoredUnit(p, q);
}

TEST(Units, DecimalPrefixesAreExact) {
  EXPECT_EQ(stored("1 mm", Quantity::kLength), 1e-3);
  EXPECT_EQ(stored("1mm", Quantity::kLength), 1e-3);
  EXPECT_EQ(stored("2 GN/m", Quantity::kStiffness), 2e9);
  EXPECT_EQ(stored("1.5e8 N/m", Quantity::kStiffness), 1.5e8);
  EXPECT_EQ(stored("2 GPa", Quantity::kPressure), 2e9);
  EXPECT_EQ(stored("2500 kg/m^3", Quantity::kDensity), 2500.0);
  EXPECT_EQ(stored("1.5 g/cm^3", Quantity::kDensity), 1500.0);
  EXPECT_EQ(stored("1e-4 s", Quantity::kTime), 1e-4);
  EXPECT_EQ(stored("5 ms", Quantity::kTime), 5e-3);
  EXPECT_EQ(stored("3 um", Quantity::kLength), 3e-6);
  EXPECT_EQ(stored("4 nm", Quantity::kLength), 4e-9);
  EXPECT_EQ(stored("7 kN", Quantity::kForce), 7e3);
  EXPECT_EQ(stored("-9.81 m/s^2", Quantity::kAcceleration), -9.81);
  EXPECT_EQ(stored("+2 Hz", Quantity::kFrequency), 2.0);
}

TEST(Units, ProductsQuotientsAndPowersAgree) {
  EXPECT_EQ(stored("2500 kg m^-3", Quantity::kDensity), 2500.0);
  EXPECT_EQ(stored("2500 kg*m^-3", Quantity::kDensity), 2500.0);
  EXPECT_EQ(stored("9.81 m s^-2", Quantity::kAcceleration), 9.81);
  EXPECT_EQ(stored("9.81 m/s/s", Quantity::kAcceleration), 9.81);
  EXPECT_EQ(stored("3 kg m/s^2", Quantity::kForce), 3.0);  // a newton
  EXPECT_EQ(stored("3 N m^-1", Quantity::kStiffness), 3.0);
  EXPECT_EQ(stored("2 /s", Quantity::kFrequency), 2.0);
  EXPECT_EQ(stored("5 min", Quantity::kTime), 300.0);  // "min" is minutes, not milli-"in"
  EXPECT_EQ(stored("2 h", Quantity::kTime), 7200.0);
}

TEST(Units, AnglesConvertToTheStoredUnit) {
  EXPECT_EQ(stored("30 deg", Quantity::kAngle), 30.0);
  EXPECT_DOUBLE_EQ(stored("0.5 rad", Quantity::kAngle), radToDeg(0.5));
  EXPECT_EQ(stored("0.5 rad", Quantity::kPhase), 0.5);
  EXPECT_DOUBLE_EQ(stored("90 deg", Quantity::kPhase), degToRad(90.0));
  EXPECT_EQ(stored("0.03 rad/s", Quantity::kAngularVelocity), 0.03);
  EXPECT_DOUBLE_EQ(stored("180 deg/s", Quantity::kAngularVelocity), kPi);
  EXPECT_EQ(stored("2 mrad", Quantity::kPhase), 2e-3);
}

TEST(Units, DimensionsAreTracked) {
  EXPECT_EQ(parseQuantity("2 GPa").dimension, dimensionOf(Quantity::kPressure));
  EXPECT_NE(parseQuantity("2 GPa").dimension, dimensionOf(Quantity::kStiffness));
  // Angles are their own dimension: a rotation rate is not a frequency.
  EXPECT_NE(parseQuantity("1 rad/s").dimension, dimensionOf(Quantity::kFrequency));
  EXPECT_EQ(toString(parseQuantity("1 N/m^2").dimension), "kg m^-1 s^-2");
  EXPECT_EQ(describe(parseQuantity("1 N/m^2").dimension), "a pressure (Pa)");
  const ParsedQuantity bare = parseQuantity(" 1e-3 ");
  EXPECT_FALSE(bare.has_unit);
  EXPECT_TRUE(bare.dimension.dimensionless());
  EXPECT_EQ(bare.value, 1e-3);
}

TEST(Units, MalformedTextIsRejected) {
  for (const char* text : {"", "mm", "abc", "2 furlongs", "2 m^", "2 m^x", "2 m//s", "2 m/", "2 *m",
                           "2 m^99", "nan m", "inf", "1e400 m", "2 m-s", "+-2 m"}) {
    EXPECT_THROW(parseQuantity(text), std::invalid_argument) << "'" << text << "'";
  }
}

}  // namespace
}  // namespace polydem::scene
