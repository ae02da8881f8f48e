// Pantelides' algorithm: which equations a higher-index model differentiates, how often, and the
// structural index it reports; a model of index 1 is left alone. The dummy derivatives that
// follow are tests/core/passes/dummy_derivatives_test.cc's.

#include "core/passes/pantelides.h"

#include <gtest/gtest.h>

#include <algorithm>

#include "tests/support/reduced_system.h"
#include "tests/support/test_models.h"

namespace momenta {
namespace {

TEST(PantelidesTest, CartesianPendulumIsOfIndexThree) {
  // x^2 + y^2 = L^2 constrains two states: differentiated twice, and der(x) = vx, der(y) = vy
  // once each, to reach the accelerations.
  testing::ReducedSystem r = testing::ReduceForPantelides(testing::kCartesianPendulum);
  const size_t equations_before = r.sys.equations.size();
  DifferentiatedSystem differentiated = Pantelides(&r.sys);
  EXPECT_EQ(differentiated.structural_index, 3u);
  EXPECT_EQ(differentiated.num_differentiated, 4u);
  EXPECT_EQ(r.sys.equations.size(), equations_before + 4);
  EXPECT_EQ(differentiated.max_order[r.Var("pendulum.x")], 2u);
  EXPECT_EQ(differentiated.max_order[r.Var("pendulum.y")], 2u);
  EXPECT_EQ(differentiated.max_order[r.Var("pendulum.vx")], 1u);
  // Each added equation is the derivative of another, and says so.
  size_t chains = 0;
  for (size_t e = 0; e < r.sys.equations.size(); ++e) {
    if (differentiated.antiderivative[e] < 0) continue;
    ++chains;
    EXPECT_EQ(differentiated.derivative[differentiated.antiderivative[e]], static_cast<int32_t>(e));
    EXPECT_GE(r.sys.flat->equations[r.sys.equations[e].origin].differentiated_from, 0);
  }
  EXPECT_EQ(chains, 4u);
}

TEST(PantelidesTest, AnIndexOneModelIsLeftAlone) {
  testing::ReducedSystem r = testing::ReduceForPantelides(R"(
model: Decay
variables:
  x: {start: 1, fixed: true}
  y: {}
equations: [der(x) = -x, y = 2*x]
)");
  const size_t equations_before = r.sys.equations.size();
  DifferentiatedSystem differentiated = Pantelides(&r.sys);
  EXPECT_EQ(differentiated.structural_index, 1u);
  EXPECT_EQ(differentiated.num_differentiated, 0u);
  EXPECT_EQ(r.sys.equations.size(), equations_before);
  EXPECT_TRUE(std::all_of(differentiated.max_order.begin(), differentiated.max_order.end(),
                          [](uint32_t k) { return k <= 1; }));
}

const char* kPendulum = R"(
model: Pendulum
define:
  Pendulum:
    parameters: {L: 1, g: 9.81}
    variables:
      x: {start: 1}
      y: {start: 0}
      vx: {}
      vy: {}
      lambda: {}
    equations:
      - der(x) = vx
      - der(y) = vy
      - der(vx) = -lambda*x
      - der(vy) = -lambda*y - g
      - x^2 + y^2 = L^2
components:
  p: {type: Pendulum}
)";

TEST(PantelidesTest, HigherIndexIsReducedNotReported) {
  // A nonlinear position constraint between two states (index 3): Pantelides' algorithm and
  // dummy derivatives reduce it (tests/physics/pendulum_test.cc checks the motion).
  EXPECT_EQ(testing::BuildError(kPendulum), "");
  // The build reports the index and what was differentiated.
  testing::Built b = testing::BuildYaml(testing::kCartesianPendulum);
  EXPECT_EQ(b.report.structural_index, 3u);
  EXPECT_EQ(b.report.differentiated.size(), 4u);
}

}  // namespace
}  // namespace momenta
