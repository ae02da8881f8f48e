// A component entry's value may name the component's own parameters, as Modelica reads a
// modifier in the enclosing scope (`BodyCylinder bodyCylinder(innerDiameter = bodyCylinder.diameter/2)`).

#include <gtest/gtest.h>

#include <string>

#include "tests/support/test_models.h"

namespace momenta {
namespace {

using testing::BuildError;
using testing::BuildYaml;
using testing::RunDefault;
using testing::Trajectory;

// A 2 kg mass on a spring c = 40 N/m whose unstretched length is written as spring.c/100 = 0.4 m,
// released at rest at s = 0.4 m: at its unstretched length, it stays there (to IDA's tolerance).
TEST(ModifierScopeTest, AValueNamesItsOwnComponentsParameter) {
  const Trajectory t = RunDefault(BuildYaml(R"(
model: Own
components:
  fixed: {type: Fixed}
  spring: {type: Spring, c: 40, s_rel0: spring.c/100}
  mass: {type: Mass, m: 2, s: {start: 0.4, fixed: true}, v: {fixed: true}}
connections:
  - [fixed.flange, spring.flange_a]
  - [spring.flange_b, mass.flange_a]
experiment: {stop: 1}
outputs: [mass.s, mass.a]
)"));
  for (size_t r = 0; r < t.t.size(); ++r) EXPECT_NEAR(t.Column("mass.s", r), 0.4, 1e-12) << "at t = " << t.t[r];
}

// A value naming its own parameter in a cycle is the cycle error, naming the parameter.
TEST(ModifierScopeTest, AValueThatNamesItselfIsACycle) {
  const std::string error = BuildError(R"(
model: Cycle
components:
  fixed: {type: Fixed}
  spring: {type: Spring, c: spring.c*2}
connections: [[fixed.flange, spring.flange_a]]
)");
  EXPECT_NE(error.find("the parameters' bindings form a cycle through spring.c"), std::string::npos) << error;
}

}  // namespace
}  // namespace momenta
