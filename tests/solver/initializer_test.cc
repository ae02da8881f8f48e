// Initialisation: Newton's method must reach consistent values even when they are far from the
// guesses (KINSOL's default step bound would stop it), and report a failure in the user's names.

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "solver/initializer.h"
#include "tests/support/test_models.h"

namespace momenta {
namespace {

TEST(InitializerTest, HugeDerivativesAreReached) {
  // A 1 fF capacitor at 1 kV discharging through 1 ohm: dv/dt = -v/(RC) = -1e18 V/s at t = 0.
  auto b = testing::BuildYaml(R"yaml(
model: FastRC
components:
  ground: {type: Ground}
  R: {type: Resistor, R: 1}
  C: {type: Capacitor, C: 1e-15, v: {start: 1000, fixed: true}}
connections:
  - [C.p, R.p]
  - [R.n, ground.p]
  - [C.n, ground.p]
experiment: {stop: 1e-14, tolerance: 1e-8, interval: 1e-15}
outputs: [C.v]
)yaml");
  ModelState state(b.model);
  state.SetParameters({});
  InitialValues init = SolveInitialization(&state, 0, false);
  ASSERT_EQ(init.yp.size(), 1u);
  // dv/dt = -v/(R C) exactly (a linear system: rounding only).
  EXPECT_NEAR(init.yp[0], -1e18, 1e18 * 1e-12);
  EXPECT_EQ(init.y[0], 1000.0);
}

TEST(InitializerTest, InconsistentInitialValuesNameTheEquation) {
  // x^2 = -1 has no real solution: the message names the equation with the largest residual.
  auto b = testing::BuildYaml(R"yaml(
model: NoSolution
variables:
  x: {start: 1}
  y: {start: 0, fixed: true}
equations:
  - x^2 + 1 = 0
  - der(y) = x
outputs: [x]
)yaml");
  ModelState state(b.model);
  state.SetParameters({});
  try {
    SolveInitialization(&state, 0, false);
    FAIL() << "expected an initialisation failure";
  } catch (const SolverError& e) {
    std::string msg = e.what();
    EXPECT_NE(msg.find("initialisation failed"), std::string::npos) << msg;
    EXPECT_NE(msg.find("x^2 + 1 = 0"), std::string::npos) << msg;
  }
}

TEST(InitializerTest, AResidualThatIsNotANumberIsTheOneNamed) {
  // b's start y = 1 puts sqrt(y - 2) outside its domain; a's and c's residuals are 0 at their
  // starts. The message names b's equation and its NaN (before: c's, "the largest remaining
  // residual, 0", since no comparison with a NaN holds).
  auto b = testing::BuildYaml(R"yaml(
model: NotANumber
define:
  Root:
    parameters:
      y0: {value: 3}
    variables:
      x: {start: 1}
      y: {start: y0}
      z: {start: 0, fixed: true}
    equations:
      - der(z) = x
      - 0 = x - 1
      - 0 = sqrt(y - 2) - 1
components:
  a: {type: Root}
  b: {type: Root, y0: 1}
  c: {type: Root}
outputs: [a.y, b.y, c.y]
)yaml");
  ModelState state(b.model);
  state.SetParameters({});
  try {
    SolveInitialization(&state, 0, false);
    FAIL() << "expected an initialisation failure";
  } catch (const SolverError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("the residual of b (Root"), std::string::npos) << msg;
    EXPECT_NE(msg.find("'0 = sqrt(y - 2) - 1' is "), std::string::npos) << msg;
    EXPECT_NE(msg.find("nan"), std::string::npos) << msg;
  }
}

TEST(InitializerTest, ASingularSystemThatHoldsIsSolved) {
  // At z = 1 the two algebraic equations are one, x + y = 2: KINSOL's LU stops at a zero pivot
  // (before: "initialisation failed (KINSOL: The linear solver's setup function failed ...)");
  // the minimum-norm Newton steps reach a solution. Any x + y = 2 holds; the residuals are checked
  // to 1e-12 (the linear system's rounding).
  auto b = testing::BuildYaml(R"yaml(
model: OneEquationTwice
variables:
  x: {start: 0}
  y: {start: 0}
  z: {start: 1, fixed: true}
equations:
  - x + y = 2
  - z*x + y = 1 + z
  - der(z) = x - y
outputs: [x, y, z]
)yaml");
  ModelState state(b.model);
  state.SetParameters({});
  InitialValues init = SolveInitialization(&state, 0, false);
  std::vector<double> z = init.y;
  for (size_t s = 0; s < b.model->num_states(); ++s) z.push_back(init.yp[b.model->state_y[s]]);
  std::vector<double> f(z.size());
  state.InitResidual(0, z.data(), f.data());
  for (double r : f) EXPECT_LT(std::fabs(r), 1e-12);
  EXPECT_LT(init.max_residual, 1e-12);
}

}  // namespace
}  // namespace momenta
