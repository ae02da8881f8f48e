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
