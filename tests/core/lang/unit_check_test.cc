// The dimension check of equations (core/lang/unit_check.h): the mistakes it reports, by their
// messages (an equation adding N to m/s, der() of the wrong unit, a connection of mismatched
// dimensions, a value in an incompatible unit, an unparsable unit string), what it must not
// report (unknown units, literals, structural ifs), and the whole library and every model passing.

#include "core/lang/unit_check.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "core/expr/expr_eval.h"
#include "core/flatten/flat_system.h"
#include "core/lang/model_spec.h"
#include "core/flatten/flatten.h"
#include "core/lang/yaml_loader.h"
#include "core/lang/builtin_library.h"

namespace momenta {
namespace {

std::string FlattenError(const std::string& yaml, const Library& library = BuiltinLibrary()) {
  try {
    ModelSpec spec = LoadModelString(yaml, "test.yaml");
    FlatSystem flat = Flatten(spec, library, {});
    EvaluateParameters(flat, {});
  } catch (const ModelError& e) {
    return e.what();
  }
  return "";
}

/// A Mass-like type whose last equation is `eq`.
std::string Thing(const std::string& eq, const std::string& extra = "") {
  return R"(model: M
define:
  Thing:
    parameters:
      m: {value: 1, unit: kg}
      k: {value: 1}
    connectors: {flange: Flange}
    variables:
      s: {unit: m}
      v: {unit: m/s}
      a: {unit: m/s2}
      u: {}
    equations:
      - v = der(s)
      - a = der(v)
      - flange.s = s
      - u*k = 0
      - )" +
         eq + "\n" + extra + R"(components:
  t: {type: Thing}
)";
}

TEST(UnitCheckTest, AnEquationAddingNewtonsToVelocityIsReported) {
  EXPECT_EQ(FlattenError(Thing("m*a = flange.f + v")),
            "test.yaml:18:26: dimension mismatch in 'm*a = flange.f + v' of Thing: the terms "
            "'flange.f' and 'v' "
            "have different dimensions: N against m/s");
}

TEST(UnitCheckTest, BothSidesOfAnEquationAgree) {
  EXPECT_EQ(FlattenError(Thing("m*a = v")),
            "test.yaml:18:9: dimension mismatch in 'm*a = v' of Thing: the two sides have "
            "different dimensions: "
            "N against m/s");
}

TEST(UnitCheckTest, DerOfTheWrongUnitIsReported) {
  // der(s) is in m/s; a is in m/s2.
  std::string yaml = Thing("m*a = flange.f");
  yaml.replace(yaml.find("a = der(v)"), 10, "a = der(s)");
  EXPECT_EQ(
      FlattenError(yaml),
      "test.yaml:15:9: dimension mismatch in 'a = der(s)' of Thing: the two sides have different "
      "dimensions: m/s2 against m/s");
}

TEST(UnitCheckTest, FunctionArgumentsRelationsAndBranchesAreChecked) {
  EXPECT_NE(FlattenError(Thing("m*a = flange.f*sin(s)"))
                .find("the argument of sin() must be dimensionless, found m"),
            std::string::npos);
  EXPECT_NE(FlattenError(Thing("m*a = if s > v then flange.f else 0"))
                .find("the two sides of '(s > v)' have different dimensions: m against m/s"),
            std::string::npos);
  EXPECT_NE(FlattenError(Thing("m*a = if s > 0 then flange.f else m*v"))
                .find("the branches of the if-expression have different dimensions: N against N.s"),
            std::string::npos);
  EXPECT_NE(FlattenError(Thing("m*a = max(flange.f, v)"))
                .find("the arguments of max() have different dimensions"),
            std::string::npos);
}

TEST(UnitCheckTest, UnknownUnitsLiteralsAndStructuralIfsAreNoMistake) {
  // u and k have no unit: they match anything. Numbers scale (2*m*a) and take the dimension of
  // what they are added to (a + 1, s > 0). sqrt, ^ and der give derived dimensions.
  EXPECT_EQ(FlattenError(Thing("2*m*a = flange.f + u*k + m*(a + 1)")), "");
  EXPECT_EQ(FlattenError(Thing("m*a = flange.f + m*sqrt(a^2) + m*(v^2/s) + m*der(v)*exp(-k*time)")),
            "");
  EXPECT_EQ(FlattenError(Thing("0 = if s > 0 then m*a - flange.f else v - 1")), "");
  EXPECT_EQ(FlattenError(Thing("m*a = flange.f", "    initial_equations:\n      - s = 0.5\n")), "");
  // A name without a unit learns it from `u = <known>` and is then checked like any other.
  std::string learnt = Thing("m*a = flange.f + u");
  learnt.replace(learnt.find("a = der(v)"), 10, "a = der(v)\n      - u = v");
  EXPECT_NE(FlattenError(learnt).find(
                "the terms 'flange.f' and 'u' have different dimensions: N against m/s"),
            std::string::npos);
}

TEST(UnitCheckTest, ParameterBindingsAndWhenStatementsAreChecked) {
  std::string yaml = Thing("m*a = flange.f");
  yaml.replace(yaml.find("k: {value: 1}"), 13, "k: {value: 2*m, unit: N}");
  EXPECT_NE(FlattenError(yaml).find(
                "in '2*m' of Thing: the value and k have different dimensions: N against kg"),
            std::string::npos);
  EXPECT_NE(
      FlattenError(Thing("m*a = flange.f",
                         "    when:\n      - when: s > 1\n        then: [\"reinit(v, -s)\"]\n"))
          .find("the value and v have different dimensions: m/s against m"),
      std::string::npos);
}

TEST(UnitCheckTest, AConnectionOfMismatchedDimensionsIsReported) {
  EXPECT_EQ(FlattenError(R"(model: M
define:
  Source:
    connectors: {y: RealOutput}
    variables: {y: {unit: N}}
    equations: [y = 1]
  Sink:
    connectors: {u: RealInput}
    variables: {u: {unit: m/s}, x: {}}
    equations: [x = u]
components:
  a: {type: Source}
  b: {type: Sink}
connections:
  - [a.y, b.u]
)"),
            "test.yaml:15:6: dimension mismatch in the connection of b.u [m/s] to a.y [N]: m/s "
            "against N");
}

TEST(UnitCheckTest, ModelEquationsAreChecked) {
  EXPECT_EQ(FlattenError(R"(model: M
components:
  mass: {type: Mass, m: 2}
variables:
  e: {unit: J}
equations:
  - e = 0.5*mass.m*mass.v
outputs: [e]
)"),
            "test.yaml:7:5: dimension mismatch in 'e = 0.5*mass.m*mass.v' of model M: the two "
            "sides have different "
            "dimensions: J against N.s");
}

TEST(UnitCheckTest, AnUnparsableUnitIsAnErrorAtItsPlace) {
  std::string yaml = Thing("m*a = flange.f");
  yaml.replace(yaml.find("a: {unit: m/s2}"), 15, "a: {unit: m/sec2}");
  EXPECT_EQ(FlattenError(yaml),
            "test.yaml:11:17: unit 'm/sec2' does not parse: unknown unit 'sec' at character 3 "
            "(write units as "
            "Modelica does: m/s2, N.m, kg.m2, 1/s, rad/s, degC), in the unit of Thing.a");
}

TEST(UnitCheckTest, ValuesWithUnitsInAFileAreConverted) {
  ModelSpec spec = LoadModelString(R"(model: M
parameters:
  mA: 2500 g
  k: {value: "10 kN/m", unit: N/m}
  w: {value: 60 rpm, unit: rad/s}
components:
  mass: {type: Mass, m: 40000 g, L: 100 cm}
  spring: {type: Spring, c: k}
  wall: {type: Fixed}
connections:
  - [wall.flange, spring.flange_a]
  - [spring.flange_b, mass.flange_a]
)",
                                   "test.yaml");
  FlatSystem flat = Flatten(spec, BuiltinLibrary(), {});
  std::vector<double> values = EvaluateParameters(flat, {});
  auto value = [&](const std::string& name) {
    for (size_t k = 0; k < flat.parameters.size(); ++k) {
      if (flat.ParameterName(ParamId(k)) == name) return values[k];
    }
    ADD_FAILURE() << "no parameter " << name;
    return std::nan("");
  };
  EXPECT_DOUBLE_EQ(value("mA"), 2500);  // no declared unit: it takes the value's, g
  EXPECT_DOUBLE_EQ(value("k"), 10000);
  EXPECT_DOUBLE_EQ(value("w"), 2 * M_PI);
  EXPECT_DOUBLE_EQ(value("mass.m"), 40);
  EXPECT_DOUBLE_EQ(value("mass.L"), 1);
  EXPECT_DOUBLE_EQ(value("spring.c"), 10000);
  EXPECT_EQ(flat.ParameterUnit(ParamId(0)), "g");
}

TEST(UnitCheckTest, AValueInAnIncompatibleUnitIsReported) {
  EXPECT_EQ(FlattenError(R"(model: M
components:
  mass: {type: Mass, m: 40 m}
)"),
            "test.yaml:3:25: the value of mass.m is in m, but mass.m is in kg: m (m) cannot be "
            "converted to kg (kg)");
  EXPECT_EQ(FlattenError(R"(model: M
parameters:
  k: {value: 3 kg, unit: N/m}
)"),
            "test.yaml:3:14: the value of M.k is in kg, but M.k is in N/m: kg (kg) cannot be "
            "converted to N/m (N/m)");
}

TEST(UnitCheckTest, EveryLibraryTypeAndModelPasses) {
  // Each library type laid out once (the check runs there); what fails later (an unconnected
  // input) is not a unit mistake. A run checks only the types a user defines (a built-in type's
  // dimensions are this test's to check), so each is laid out here as if the user had written it.
  for (const std::string& type : BuiltinLibrary().ComponentNames()) {
    Library as_written;
    as_written.SetBase(&BuiltinLibrary());
    ComponentType copy = *BuiltinLibrary().FindComponent(type);
    copy.user_defined = true;
    as_written.AddComponent(std::move(copy));
    std::string error = FlattenError("model: M\ncomponents:\n  x: {type: " + type + "}\n", as_written);
    EXPECT_EQ(error.find("dimension mismatch"), std::string::npos) << type << ": " << error;
    EXPECT_EQ(error.find("does not parse"), std::string::npos) << type << ": " << error;
  }
  int models = 0;
  for (const char* dir : {"models", "models/msl"}) {
    for (const auto& f :
         std::filesystem::directory_iterator(std::string(MOMENTA_SOURCE_DIR) + "/" + dir)) {
      if (f.path().extension() != ".yaml") continue;
      ModelSpec spec = LoadModelFile(f.path().string());
      EXPECT_NO_THROW(Flatten(spec, BuiltinLibrary(), {})) << f.path();
      ++models;
    }
  }
  EXPECT_GE(models, 20);
}

}  // namespace
}  // namespace momenta
