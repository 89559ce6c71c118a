// Case-file quantities convert to SI (m, kg, s, rad) exactly, and every malformed quantity is
// rejected with a reason that names the problem.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

#include "bagdem/units.hpp"

using namespace bagdem;

namespace {

constexpr double pi = std::numbers::pi;

// SI value of a quantity that must parse; NaN (and a test failure) if it does not.
double si(std::string_view text, Dimension expected) {
  std::string why;
  const std::optional<double> v = parse_quantity(text, expected, &why);
  EXPECT_TRUE(v.has_value()) << "'" << text << "' rejected: " << why;
  return v.value_or(std::nan(""));
}

// Reason a quantity is rejected; a test failure if it is accepted.
std::string why_rejected(std::string_view text, Dimension expected) {
  std::string why;
  const std::optional<double> v = parse_quantity(text, expected, &why);
  EXPECT_FALSE(v.has_value()) << "'" << text << "' accepted as " << v.value_or(0.0);
  return why;
}

}  // namespace

TEST(UnitsParse, ConvertsCaseFileQuantitiesToSi) {
  EXPECT_DOUBLE_EQ(si("4 mm", dim::length), 0.004);
  EXPECT_DOUBLE_EQ(si("0.8 mm", dim::length), 0.0008);
  EXPECT_DOUBLE_EQ(si("30 Hz", dim::frequency), 30.0);
  EXPECT_DOUBLE_EQ(si("200 GPa", dim::pressure), 2e11);
  EXPECT_DOUBLE_EQ(si("9.81 m/s^2", dim::acceleration), 9.81);
  EXPECT_DOUBLE_EQ(si("1e-7 s", dim::time), 1e-7);
  EXPECT_DOUBLE_EQ(si("5 %", dim::none), 0.05);
  EXPECT_DOUBLE_EQ(si("2 kN/m", dim::stiffness), 2000.0);
  EXPECT_DOUBLE_EQ(si("1 N*m", dim::energy), 1.0);
  EXPECT_DOUBLE_EQ(si("2 bar", dim::pressure), 2e5);
  EXPECT_DOUBLE_EQ(si("3 mJ", dim::energy), 3e-3);
  EXPECT_DOUBLE_EQ(si("1.5 kW", Dimension{2, 1, -3, 0}), 1500.0);
}

TEST(UnitsParse, GramsPerCubicCentimetreIsThousandsOfKgPerCubicMetre) {
  // 1 g/cm^3 = 1e-3 kg / 1e-6 m^3 = 1000 kg/m^3
  EXPECT_NEAR(si("7.8 g/cm^3", dim::density), 7800.0, 7800.0 * 1e-12);
  EXPECT_NEAR(si("2500 kg/m^3", dim::density), 2500.0, 2500.0 * 1e-12);
}

TEST(UnitsParse, AnglesAreInRadians) {
  EXPECT_DOUBLE_EQ(si("45 deg", dim::angle), pi / 4);
  EXPECT_DOUBLE_EQ(si("0.5 rev", dim::angle), pi);
  EXPECT_DOUBLE_EQ(si("2 rad", dim::angle), 2.0);
}

TEST(UnitsParse, RpmIsCyclesPerSecondLikeHz) {
  EXPECT_DOUBLE_EQ(si("3000 rpm", dim::frequency), 50.0);
  // Spelled out, a revolution is an angle: rev/min is an angular speed in rad/s.
  EXPECT_DOUBLE_EQ(si("3000 rev/min", Dimension{0, 0, -1, 1}), 100 * pi);
}

TEST(UnitsParse, ExactUnitBeatsPrefixedUnit) {
  EXPECT_DOUBLE_EQ(si("2 m", dim::length), 2.0);
  EXPECT_DOUBLE_EQ(si("2 min", dim::time), 120.0);
  EXPECT_DOUBLE_EQ(si("2 mm", dim::length), 2e-3);
  EXPECT_DOUBLE_EQ(si("2 ms", dim::time), 2e-3);
  EXPECT_DOUBLE_EQ(si("2 h", dim::time), 7200.0);
  EXPECT_DOUBLE_EQ(si("2 kg", dim::mass), 2.0);
  EXPECT_DOUBLE_EQ(si("2 g", dim::mass), 2e-3);
  EXPECT_DOUBLE_EQ(si("2 kHz", dim::frequency), 2000.0);
  EXPECT_DOUBLE_EQ(si("2 MPa", dim::pressure), 2e6);
  EXPECT_DOUBLE_EQ(si("2 nm", dim::length), 2e-9);
}

TEST(UnitsParse, MicroHasThreeSpellings) {
  EXPECT_DOUBLE_EQ(si("3 um", dim::length), 3e-6);
  EXPECT_DOUBLE_EQ(si("3 \xC2\xB5m", dim::length), 3e-6);  // micro sign
  EXPECT_DOUBLE_EQ(si("3 \xCE\xBCs", dim::time), 3e-6);    // Greek mu
}

TEST(UnitsParse, ProductAndQuotientSpellingsAgree) {
  for (const char* text : {"9.81 m/s^2", "9.81 m/s/s", "9.81 m s^-2", "9.81 m*s^-2", "9.81 m.s^-2",
                           "9.81 m / s^2", "9.81m/s^2", "9.81 m^+1 s^-2"})
    EXPECT_DOUBLE_EQ(si(text, dim::acceleration), 9.81) << text;
  EXPECT_DOUBLE_EQ(si("50 1/s", dim::frequency), 50.0);
  EXPECT_DOUBLE_EQ(si("50/s", dim::frequency), 50.0);
  EXPECT_DOUBLE_EQ(si("1 kg m^2/s^2", dim::energy), 1.0);
}

TEST(UnitsParse, PlainNumberIsSiForAnyDimension) {
  EXPECT_DOUBLE_EQ(si("0.004", dim::length), 0.004);
  EXPECT_DOUBLE_EQ(si("2650", dim::density), 2650.0);
  EXPECT_DOUBLE_EQ(si("7e10", dim::pressure), 7e10);
  EXPECT_DOUBLE_EQ(si(".5", dim::none), 0.5);
  EXPECT_DOUBLE_EQ(si("  -3.5\t", dim::speed), -3.5);
  EXPECT_DOUBLE_EQ(si(" 1e-7 ", dim::time), 1e-7);
}

TEST(UnitsParse, SurroundingWhitespaceAndNoSpaceBeforeUnit) {
  EXPECT_DOUBLE_EQ(si("  4 mm \n", dim::length), 0.004);
  EXPECT_DOUBLE_EQ(si("4mm", dim::length), 0.004);
  EXPECT_DOUBLE_EQ(si("-1.5e3 Pa", dim::pressure), -1500.0);
}

TEST(UnitsErrors, EmptyText) {
  EXPECT_EQ(why_rejected("", dim::length), "empty quantity");
  EXPECT_EQ(why_rejected("  \t ", dim::length), "empty quantity");
}

TEST(UnitsErrors, NoNumber) {
  EXPECT_EQ(why_rejected("mm", dim::length), "no number in 'mm'");
  EXPECT_EQ(why_rejected("abc 4", dim::length), "no number in 'abc 4'");
}

TEST(UnitsErrors, NotFinite) {
  for (const char* text : {"nan", "inf", "-inf mm", "NaN m", "1e999", "infinity"})
    EXPECT_NE(why_rejected(text, dim::length).find("not a finite number"), std::string::npos) << text;
}

TEST(UnitsErrors, OverflowAfterConversion) {
  EXPECT_NE(why_rejected("1e300 GPa^9", Dimension{-9, 9, -18, 0}).find("out of range"),
            std::string::npos);
}

TEST(UnitsErrors, UnknownUnitIsNamed) {
  EXPECT_EQ(why_rejected("5 mmm", dim::length), "unknown unit 'mmm'");
  EXPECT_EQ(why_rejected("5 ft", dim::length), "unknown unit 'ft'");
  EXPECT_EQ(why_rejected("5 kmin", dim::time), "unknown unit 'kmin'");  // min takes no prefix
  EXPECT_EQ(why_rejected("5 kg/m^3 x", dim::density), "unknown unit 'x'");
}

TEST(UnitsErrors, TrailingGarbage) {
  EXPECT_EQ(why_rejected("5 m)", dim::length), "unexpected character ')' in 'm)'");
  EXPECT_EQ(why_rejected("5 m 2", dim::length), "unexpected character '2' in 'm 2'");
  EXPECT_EQ(why_rejected("5 m/", dim::length), "missing unit after '/' in 'm/'");
  EXPECT_EQ(why_rejected("5 m//s", dim::speed), "misplaced '/' in 'm//s'");
  EXPECT_EQ(why_rejected("5 *m", dim::length), "misplaced '*' in '*m'");
  EXPECT_EQ(why_rejected("5 1 s", dim::time), "expected '/' after '1' in '1 s'");
}

TEST(UnitsErrors, BadExponent) {
  for (const char* text : {"5 m^", "5 m^x", "5 m^1.5", "5 m^-", "5 m^+-2", "5 m^99"}) {
    const std::string why = why_rejected(text, dim::length);
    EXPECT_NE(why.find("bad exponent after 'm'"), std::string::npos) << text << ": " << why;
  }
}

TEST(UnitsErrors, DimensionMismatchNamesBothUnits) {
  EXPECT_EQ(why_rejected("5 m/s", dim::length), "has dimension m/s, expected m");
  EXPECT_EQ(why_rejected("5 %", dim::length), "has dimension 1, expected m");
  EXPECT_EQ(why_rejected("3000 rpm", dim::angle), "has dimension 1/s, expected rad");
  EXPECT_EQ(why_rejected("200 GPa", dim::force), "has dimension kg/m/s^2, expected kg m/s^2");
}

TEST(UnitsErrors, NullWhyIsAllowed) {
  EXPECT_FALSE(parse_quantity("5 mmm", dim::length).has_value());
  EXPECT_DOUBLE_EQ(parse_quantity("5 mm", dim::length).value_or(0.0), 0.005);
}

TEST(UnitsSiUnit, RendersExponentsAsSiUnits) {
  EXPECT_EQ(dim::density.si_unit(), "kg/m^3");
  EXPECT_EQ(dim::acceleration.si_unit(), "m/s^2");
  EXPECT_EQ(dim::force.si_unit(), "kg m/s^2");
  EXPECT_EQ(dim::none.si_unit(), "1");
  EXPECT_EQ(dim::frequency.si_unit(), "1/s");
  EXPECT_EQ(dim::angle.si_unit(), "rad");
  EXPECT_EQ(dim::pressure.si_unit(), "kg/m/s^2");
  EXPECT_EQ(dim::energy.si_unit(), "kg m^2/s^2");
  EXPECT_EQ(dim::stiffness.si_unit(), "kg/s^2");
}

TEST(UnitsSiUnit, RenderedUnitParsesBackToItsDimension) {
  for (Dimension d : {dim::length, dim::mass, dim::time, dim::angle, dim::frequency, dim::speed,
                      dim::acceleration, dim::density, dim::pressure, dim::force, dim::energy,
                      dim::stiffness, Dimension{0, 0, -1, 1}}) {
    EXPECT_DOUBLE_EQ(si("1 " + d.si_unit(), d), 1.0) << d.si_unit();
  }
}
