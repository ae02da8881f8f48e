// Unit strings: every spelling the library uses parses, with the dimension SI gives it; prefixes,
// exponents, quotients, parentheses; values convert between units (10 kN/m -> 10000 N/m,
// 2500 g -> 2.5 kg, rpm, deg, degC); what does not parse is reported with the string and why; the
// loader's checks (CheckUnitString, ValueInUnit) name the place, the value's owner and both units.

#include "core/lang/units.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <regex>
#include <set>

namespace momenta {
namespace {

std::string Dim(const std::string& unit) { return DimensionText(ParseUnit(unit).dimension); }

std::string ParseError(const std::string& unit) {
  try {
    ParseUnit(unit);
  } catch (const UnitError& e) {
    return e.what();
  }
  return "";
}

TEST(UnitsTest, EverySpellingInTheLibraryParses) {
  // Every `unit:` string in components/*.yaml and models/ (read from the files, so a new spelling
  // is covered the day it is written).
  std::set<std::string> units;
  const std::regex unit_re(R"re(unit:\s*("([^"]*)"|([^,}\s]+)))re");
  for (const char* dir : {"components", "models", "models/msl"}) {
    for (const auto& f :
         std::filesystem::directory_iterator(std::string(MOMENTA_SOURCE_DIR) + "/" + dir)) {
      if (f.path().extension() != ".yaml") continue;
      std::ifstream in(f.path());
      std::string line;
      while (std::getline(in, line)) {
        for (std::sregex_iterator m(line.begin(), line.end(), unit_re), end; m != end; ++m) {
          units.insert((*m)[2].matched ? (*m)[2].str() : (*m)[3].str());
        }
      }
    }
  }
  EXPECT_GE(units.size(), 20u);
  for (const auto& u : units) EXPECT_EQ(ParseError(u), "") << u;
}

TEST(UnitsTest, DerivedUnitsHaveTheirSiDimensions) {
  EXPECT_EQ(Dim("N"), "N");
  EXPECT_EQ(Dim("kg.m/s2"), "N");
  EXPECT_EQ(Dim("kg*m/s^2"), "N");
  EXPECT_EQ(Dim("N.m"), "N.m");
  EXPECT_EQ(Dim("J"), "N.m");  // one dimension: the first name of the table shows it
  EXPECT_EQ(Dim("W.s"), "N.m");
  EXPECT_EQ(Dim("m/s2"), "m/s2");
  EXPECT_EQ(Dim("m.s-2"), "m/s2");
  EXPECT_EQ(Dim("rad/s"), "1/s");  // rad is dimensionless, as in SI
  EXPECT_EQ(Dim("Hz"), "1/s");
  EXPECT_EQ(Dim("1/s"), "1/s");
  EXPECT_EQ(Dim("N.m/rad"), "N.m");
  EXPECT_EQ(Dim("N.m.s/rad"), "N.m.s");
  EXPECT_EQ(Dim("kg.m2"), "kg.m2");
  EXPECT_EQ(Dim("V/A"), "Ohm");
  EXPECT_EQ(Dim("Ohm"), "Ohm");
  EXPECT_EQ(Dim("A.s/V"), "F");
  EXPECT_EQ(Dim("V.s/A"), "H");
  EXPECT_EQ(Dim("N.m/(rad.s)"), "W");
  EXPECT_EQ(Dim("1"), "1");
  EXPECT_EQ(Dim("rad"), "1");
  EXPECT_EQ(Dim("deg"), "1");
  EXPECT_EQ(Dim("rpm"), "1/s");
  EXPECT_EQ(Dim("degC"), "K");
  EXPECT_EQ(Dim("mol/s"), "mol/s");
  EXPECT_EQ(Dim("kg.m2/(s3.A)"), "V");
  // A dimension with no common name is written in SI base units.
  EXPECT_EQ(Dim("kg.m2/(s3.A2.K)"), "m2.kg/(s3.A2.K)");
}

TEST(UnitsTest, PrefixesScaleAndWholeNamesWin) {
  EXPECT_DOUBLE_EQ(ParseUnit("kN").factor, 1e3);
  EXPECT_DOUBLE_EQ(ParseUnit("mm").factor, 1e-3);
  EXPECT_DOUBLE_EQ(ParseUnit("ms").factor, 1e-3);
  EXPECT_DOUBLE_EQ(ParseUnit("g").factor, 1e-3);
  EXPECT_DOUBLE_EQ(ParseUnit("mg").factor, 1e-6);
  EXPECT_DOUBLE_EQ(ParseUnit("uF").factor, 1e-6);
  EXPECT_DOUBLE_EQ(ParseUnit("MPa").factor, 1e6);
  EXPECT_DOUBLE_EQ(ParseUnit("hPa").factor, 1e2);
  EXPECT_DOUBLE_EQ(ParseUnit("kN/m").factor, 1e3);
  EXPECT_DOUBLE_EQ(ParseUnit("cm2").factor, 1e-4);  // the exponent applies to the prefixed unit
  // Whole names before prefix + name: min is the minute, cd the candela, Pa the pascal.
  EXPECT_DOUBLE_EQ(ParseUnit("min").factor, 60);
  EXPECT_EQ(Dim("min"), "s");
  EXPECT_EQ(Dim("cd"), "cd");
  EXPECT_EQ(Dim("Pa"), "Pa");
}

TEST(UnitsTest, ValuesConvertToTheTargetUnit) {
  EXPECT_DOUBLE_EQ(ConvertValue(10, "kN/m", "N/m"), 10000);
  EXPECT_DOUBLE_EQ(ConvertValue(2500, "g", "kg"), 2.5);
  EXPECT_DOUBLE_EQ(ConvertValue(60, "rpm", "rad/s"), 2 * M_PI);
  EXPECT_DOUBLE_EQ(ConvertValue(180, "deg", "rad"), M_PI);
  EXPECT_DOUBLE_EQ(ConvertValue(M_PI / 2, "rad", "deg"), 90);
  EXPECT_DOUBLE_EQ(ConvertValue(25, "degC", "K"), 298.15);
  EXPECT_DOUBLE_EQ(ConvertValue(300, "K", "degC"), 300 - 273.15);
  EXPECT_DOUBLE_EQ(ConvertValue(1, "h", "s"), 3600);
  EXPECT_DOUBLE_EQ(ConvertValue(2, "bar", "Pa"), 2e5);
  EXPECT_DOUBLE_EQ(ConvertValue(1, "N.m", "J"), 1);
  try {
    ConvertValue(1, "kN/m", "kg");
    ADD_FAILURE() << "converted N/m to kg";
  } catch (const UnitError& e) {
    EXPECT_STREQ(e.what(), "kN/m (N/m) cannot be converted to kg (kg)");
  }
}

TEST(UnitsTest, ValuesOutsideDoublesRangeAreNamed) {
  auto message = [](auto f) -> std::string {
    try {
      f();
    } catch (const UnitError& e) {
      return e.what();
    }
    return "";
  };
  const std::string range = "outside double's range (magnitudes from 2.2e-308";
  for (const char* text : {"1e999 kg", "-1e999 kg", "3e308 mm", "1e-320 g", "2e-308 m"}) {
    const std::string m = message([&] { SplitQuantity(text); });
    EXPECT_NE(m.find("the number " + std::string(text).substr(0, std::string(text).find(' ')) +
                     " is " + range),
              std::string::npos)
        << text << ": " << m;
  }
  // Zero in any spelling, and the smallest normal double, are numbers.
  EXPECT_EQ(SplitQuantity("0e-999 kg")->value, 0);
  EXPECT_EQ(SplitQuantity("-0.0 kg")->value, 0);
  EXPECT_EQ(SplitQuantity("2.2250738585072014e-308 kg")->value, 2.2250738585072014e-308);
  // A conversion that leaves the range; -273.15 degC is 0 K, not an underflow.
  EXPECT_NE(message([] { ConvertValue(1e306, "Mg", "kg"); }).find("1e306 Mg is inf kg, " + range),
            std::string::npos);
  EXPECT_NE(message([] { ConvertValue(1e-300, "yg", "kg"); }).find("outside double's range"),
            std::string::npos);
  EXPECT_DOUBLE_EQ(ConvertValue(-273.15, "degC", "K"), 0);
  // Hex, inf and spaces are not decimal numbers.
  for (const char* text : {"0x10", "inf", "nan", " 1", "1 ", "1e", "e5", "+", "1.2.3"}) {
    EXPECT_FALSE(ParseDecimal(text)) << text;
  }
  for (const char* text : {"1", "-1.5", "+.5", "5.", "1e5", "1E-5", "0"}) {
    EXPECT_TRUE(ParseDecimal(text)) << text;
  }
}

TEST(UnitsTest, ParenthesesNestAtMostTheNestingLimit) {
  auto nested = [](int n) { return std::string(n, '(') + "m" + std::string(n, ')'); };
  EXPECT_EQ(ParseUnit(nested(256)).factor, 1);
  try {
    ParseUnit(nested(20000));
    ADD_FAILURE() << "20 000 parentheses parsed";
  } catch (const UnitError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("parentheses nested deeper than 256 levels at character 257"), std::string::npos) << m.substr(0, 300);
    EXPECT_LT(m.size(), 500u);
  }
  // A scale beyond double's range: (km)^999 would be 1e2997.
  try {
    ParseUnit("km999");
    ADD_FAILURE() << "km999 parsed";
  } catch (const UnitError& e) {
    EXPECT_NE(std::string(e.what()).find("its scale to SI units is outside double's range"), std::string::npos) << e.what();
  }
}

TEST(UnitsTest, QuantitiesSplitIntoNumberAndUnit) {
  auto q = SplitQuantity("10kN/m");
  ASSERT_TRUE(q);
  EXPECT_EQ(q->value, 10);
  EXPECT_EQ(q->unit, "kN/m");
  q = SplitQuantity(" 2500 g ");
  ASSERT_TRUE(q);
  EXPECT_EQ(q->value, 2500);
  EXPECT_EQ(q->unit, "g");
  q = SplitQuantity("-1.5e3 m/s2");
  ASSERT_TRUE(q);
  EXPECT_EQ(q->value, -1500);
  EXPECT_EQ(q->unit, "m/s2");
  EXPECT_THROW(SplitQuantity("5 eV"), UnitError);  // 'e' is no exponent here, and eV no unit
  EXPECT_FALSE(SplitQuantity("1e3"));
  EXPECT_FALSE(SplitQuantity("2*m"));
  EXPECT_FALSE(SplitQuantity("m"));
  EXPECT_FALSE(SplitQuantity("2.5"));
  EXPECT_FALSE(SplitQuantity("[1, 2]"));
  EXPECT_THROW(SplitQuantity("3 mps"), UnitError);
}

TEST(UnitsTest, WhatDoesNotParseIsNamed) {
  EXPECT_EQ(
      ParseError("mps"),
      "unit 'mps' does not parse: unknown unit 'mps' at character 1 (write units as Modelica does: "
      "m/s2, N.m, kg.m2, 1/s, rad/s, degC)");
  EXPECT_NE(ParseError("m/").find("a unit name is missing at the end"), std::string::npos);
  EXPECT_NE(ParseError("N.m/(rad.s").find("a missing ')'"), std::string::npos);
  EXPECT_NE(ParseError("m^x").find("an exponent must be a whole number"), std::string::npos);
  EXPECT_NE(ParseError("").find("an empty unit string"), std::string::npos);
  EXPECT_NE(ParseError("m s").find("unexpected ' '"), std::string::npos);
  EXPECT_NE(ParseError("degC.m").find("degC is an offset unit"), std::string::npos);
  EXPECT_NE(ParseError("kkg").find("unknown unit 'kkg'"), std::string::npos);  // kg takes no prefix
}

/// The message of a ModelError that `f` throws, or "" when it throws none.
template <typename F>
std::string ModelErrorOf(F f) {
  try {
    f();
  } catch (const ModelError& e) {
    return e.what();
  }
  return "";
}

TEST(UnitsTest, ValueInUnitConvertsToTheDeclaredUnit) {
  EXPECT_EQ(ValueInUnit(10, "kN/m", "N/m", "spring.c", SourceLoc("m.yaml", 3, 7))->number, 10000);
  EXPECT_EQ(ValueInUnit(2500, "g", "kg", "mass.m", SourceLoc("m.yaml", 3, 7))->number, 2.5);
}

TEST(UnitsTest, ValueInUnitNamesTheOwnerAndBothUnits) {
  const SourceLoc loc("m.yaml", 3, 7);
  EXPECT_EQ(ModelErrorOf([&] { ValueInUnit(40, "kg", "", "body.x", loc); }),
            "m.yaml:3:7: body.x declares no unit, so a value in kg cannot be converted; give it as a "
            "plain number");
  const std::string wrong = ModelErrorOf([&] { ValueInUnit(40, "kg", "m", "body.x", loc); });
  EXPECT_EQ(wrong.rfind("m.yaml:3:7: the value of body.x is in kg, but body.x is in m: ", 0), 0u)
      << wrong;
}

TEST(UnitsTest, CheckUnitStringNamesThePlaceAndWhoseUnit) {
  const SourceLoc loc("m.yaml", 4, 11);
  EXPECT_EQ(ModelErrorOf([&] { CheckUnitString("N.m/rad", loc, "the unit of Spring.c"); }), "");
  const std::string message = ModelErrorOf([&] { CheckUnitString("mps", loc, "the unit of Mass.v"); });
  EXPECT_EQ(message.rfind("m.yaml:4:11: unit 'mps' does not parse: unknown unit 'mps'", 0), 0u) << message;
  EXPECT_NE(message.find(", in the unit of Mass.v"), std::string::npos) << message;
}

}  // namespace
}  // namespace momenta
