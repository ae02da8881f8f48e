// Parameters declared `evaluate: true` (core/passes/structural_conditions.h): their values are
// fixed when the model is built, so a zero one multiplying der() leaves no state (the MSL's
// HeatingNPN_NORGate has capacitors of CapVal = 0 with Evaluate = true).

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "tests/support/test_models.h"

namespace momenta::testing {
namespace {

// A 1 V step charges C2 = 1 mF through R = 1 kOhm (tau = 1 s); C1 = CapVal across C2. With
// CapVal = 0 evaluated, C1 carries no current and its voltage is no state: one state, and
// C2.v = 1 - exp(-t). Kept as a parameter (the old behaviour), C1.v is a second state whose
// derivative nothing determines (the NOR gates' initialisation fails there).
std::string Circuit(const std::string& capval) {
  return R"(
model: ZeroCapacitance
parameters:
  CapVal: )" + capval + R"(
components:
  G: {type: Ground}
  V: {type: ConstantVoltage, V: 1}
  R: {type: Resistor, R: 1000}
  C1: {type: Capacitor, C: CapVal}
  C2: {type: Capacitor, C: 1e-3, v: {start: 0, fixed: true}}
connections:
  - [V.p, R.p]
  - [R.n, C1.p]
  - [R.n, C2.p]
  - [C1.n, G.p]
  - [C2.n, G.p]
  - [V.n, G.p]
experiment: {start: 0, stop: 2, interval: 0.5, tolerance: 1e-8}
outputs: [C2.v, C1.v, C1.i]
)";
}

TEST(EvaluatedParametersTest, AZeroCapacitanceLeavesNoState) {
  Built b = BuildYaml(Circuit("{value: 0, unit: F, evaluate: true}"));
  EXPECT_EQ(b.model->num_states(), 1u);
  Trajectory t = RunDefault(b);
  for (size_t k = 0; k < t.t.size(); ++k) {
    // Closed form to 1e-6 V (the run's rtol 1e-8 on a 1 V signal, with margin).
    EXPECT_NEAR(t.Column("C2.v", k), 1 - std::exp(-t.t[k]), 1e-6) << t.t[k];
    EXPECT_EQ(t.Column("C1.i", k), 0.0) << t.t[k];
    EXPECT_NEAR(t.Column("C1.v", k), t.Column("C2.v", k), 1e-12) << t.t[k];
  }
}

TEST(EvaluatedParametersTest, ANonZeroValueIsAnOrdinaryCapacitor) {
  // CapVal = 1 mF evaluated: C1 and C2 in parallel, tau = 2 s; both stay capacitors (C1.v is
  // not fixed, so one of the two parallel voltages is the state).
  Built b = BuildYaml(Circuit("{value: 1e-3, unit: F, evaluate: true}"));
  Trajectory t = RunDefault(b);
  for (size_t k = 0; k < t.t.size(); ++k) {
    EXPECT_NEAR(t.Column("C2.v", k), 1 - std::exp(-t.t[k] / 2), 1e-6) << t.t[k];
  }
}

TEST(EvaluatedParametersTest, AnEvaluatedParameterIsStructural) {
  Built b = BuildYaml(Circuit("{value: 0, unit: F, evaluate: true}"));
  EXPECT_TRUE(b.model->flat->StructuralValue("CapVal") != nullptr);
  EXPECT_TRUE(b.model->flat->StructuralValue("C1.C") != nullptr);  // bound to CapVal alone
  EXPECT_TRUE(b.model->flat->StructuralValue("C2.C") == nullptr);  // a number: an ordinary parameter
}

// A conditional block whose condition reads a Real parameter (the MSL's LineForceWithTwoMasses,
// `if m_a > 0 or m_b > 0`): the branch is chosen when the model is built, as Modelica evaluates an
// if-equation's parameter condition, and the parameters it reads become structural. Before, the
// block stayed an if-expression and both branches were equations ("Block is unbalanced: 3
// equations for 2 unknowns").
std::string Block(const std::string& m) {
  return R"(
model: Block
define:
  Decay:
    parameters:
      m: {value: 1}
      big: {value: m > 0, type: Boolean}
    variables:
      x: {start: 1, fixed: true}
      y: {}
    equations:
      - der(x) = -y
      - if: big
        then:
          - y = m*x
        else:
          - y = 0
components:
  d: {type: Decay, m: )" + m + R"(}
experiment: {start: 0, stop: 1, interval: 0.25, tolerance: 1e-8}
outputs: [d.x]
)";
}

TEST(EvaluatedParametersTest, ABlockConditionOfRealParametersChoosesTheBranch) {
  // m = 2: x' = -2x, x = exp(-2t) (to 1e-6: the run's rtol 1e-8 on a value below 1, with margin).
  Built decaying = BuildYaml(Block("2"));
  EXPECT_TRUE(decaying.model->flat->StructuralValue("d.m") != nullptr);
  EXPECT_TRUE(decaying.model->flat->StructuralValue("d.big") != nullptr);
  Trajectory t = RunDefault(decaying);
  for (size_t k = 0; k < t.t.size(); ++k) EXPECT_NEAR(t.Column("d.x", k), std::exp(-2 * t.t[k]), 1e-6) << t.t[k];
  // m = 0: the else branch, y = 0, and x stays 1 exactly.
  Trajectory held = RunDefault(BuildYaml(Block("0")));
  for (size_t k = 0; k < held.t.size(); ++k) EXPECT_EQ(held.Column("d.x", k), 1.0) << held.t[k];
}

}  // namespace
}  // namespace momenta::testing
