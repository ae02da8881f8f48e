// Initialisation: Newton's method must reach consistent values even when they are far from the
// guesses (KINSOL's default step bound would stop it), and report a failure in the user's names.

#include <gtest/gtest.h>

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

}  // namespace
}  // namespace momenta
