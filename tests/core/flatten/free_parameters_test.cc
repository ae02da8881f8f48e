// Parameters computed at the start (`c: {fixed: false, start: 20}`, Modelica's fixed = false;
// core/flatten/free_parameters.h): the initial conditions determine them with the states, and
// they stay constant afterwards.

#include <gtest/gtest.h>

#include <string>

#include "tests/support/test_models.h"

namespace momenta {
namespace {

using testing::BuildError;
using testing::BuildYaml;
using testing::RunDefault;
using testing::Trajectory;

// A 2 kg mass pulled by a constant 19.6 N rests on a spring from a wall, 0.5 m out, with s_rel0 =
// 0.1 m: the spring constant that holds it there (v = 0, a = 0) is c = 19.6 / 0.4 = 49 N/m.
std::string Hanging(const std::string& spring) {
  return R"(
model: Hanging
define:
  DoubledSpring:
    doc: a spring whose law reads k = 2 c, a parameter computed from c
    parameters:
      c: {value: 1}
      k: {value: 2*c}
      s_rel0: {value: 0}
    connectors: {flange_a: {type: Flange}, flange_b: {type: Flange}}
    variables: {s_rel: {}, f: {}}
    equations:
      - s_rel = flange_b.s - flange_a.s
      - flange_b.f = f
      - flange_a.f = -f
      - f = k/2*(s_rel - s_rel0)
components:
  fixed: {type: Fixed}
  spring: )" + spring + R"(
  mass: {type: Mass, m: 2, s: {start: 0.5, fixed: true}, v: {fixed: true}, a: {fixed: true}}
  force: {type: ConstantForce, f_constant: 19.6}
connections:
  - [fixed.flange, spring.flange_a]
  - [spring.flange_b, mass.flange_a]
  - [force.flange, mass.flange_b]
experiment: {stop: 2}
outputs: [mass.s, spring.c]
)";
}

// c is computed at the start to rounding (a linear problem for Newton) and stays constant to the
// last bit (its equation is der(c) = 0); the mass stays at rest to IDA's tolerance.
TEST(FreeParametersTest, TheInitialConditionsDetermineTheSpringConstant) {
  const Trajectory t = RunDefault(BuildYaml(Hanging("{type: Spring, c: {fixed: false, start: 20}, s_rel0: 0.1}")));
  ASSERT_GT(t.t.size(), 2u);
  const double c0 = t.Column("spring.c", 0);
  EXPECT_NEAR(c0, 49.0, 1e-9);
  for (size_t r = 0; r < t.t.size(); ++r) {
    EXPECT_EQ(t.Column("spring.c", r), c0) << "at t = " << t.t[r];
    EXPECT_NEAR(t.Column("mass.s", r), 0.5, 1e-9) << "at t = " << t.t[r];
  }
}

// -p sets the parameter, which is the guess for the variable: the answer is the same.
TEST(FreeParametersTest, MinusPSetsTheGuessOnly) {
  const Trajectory t = RunDefault(BuildYaml(Hanging("{type: Spring, c: {fixed: false}, s_rel0: 0.1}")),
                                  {{"spring.c", 3.0}});
  EXPECT_NEAR(t.Column("spring.c", 0), 49.0, 1e-9);
}

// A parameter computed from a free one (k = 2 c) is computed at the start too.
TEST(FreeParametersTest, AParameterComputedFromAFreeOneFollowsIt) {
  const Trajectory t = RunDefault(BuildYaml(Hanging("{type: DoubledSpring, c: {fixed: false, start: 5}, s_rel0: 0.1}")));
  EXPECT_NEAR(t.Column("spring.c", 0), 49.0, 1e-9);
  EXPECT_NEAR(t.Column("mass.s", t.t.size() - 1), 0.5, 1e-9);
}

TEST(FreeParametersTest, ErrorsNameTheParameter) {
  EXPECT_NE(BuildError(Hanging("{type: Spring, c: {fixed: true}, s_rel0: 0.1}"))
                .find("spring.c is a parameter: give it a value, e.g. c: 2, or {fixed: false, start: 2}"),
            std::string::npos);
  EXPECT_NE(BuildError(Hanging("{type: Spring, c: {fixed: false, nominal: 10}, s_rel0: 0.1}"))
                .find("spring.c is a parameter with fixed: false: it takes start and fixed only"),
            std::string::npos);
}

// A structural parameter (evaluate: true) is fixed when the model is built: it cannot wait for
// the initial conditions.
TEST(FreeParametersTest, AStructuralParameterCannotBeFree) {
  const std::string model = R"(
model: Structural
define:
  Holder:
    parameters: {c: {value: 1, evaluate: true}}
    connectors: {flange: {type: Flange}}
    equations: [flange.f = c*flange.s]
components:
  holder: {type: Holder, c: {fixed: false, start: 2}}
  mass: {type: Mass, m: 1, s: {start: 1, fixed: true}, v: {fixed: true}}
connections: [[holder.flange, mass.flange_a]]
)";
  EXPECT_NE(BuildError(model).find("holder.c is evaluated when the model is built (evaluate: true), so it cannot be "
                                   "computed at the start (fixed: false)"),
            std::string::npos)
      << BuildError(model);
}

}  // namespace
}  // namespace momenta
