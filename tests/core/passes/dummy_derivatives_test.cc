// The dummy derivatives after Pantelides' algorithm: which derivatives become algebraic
// variables, and the dynamic state sets a pendulum in Cartesian coordinates needs (no one pair
// of states serves the whole swing).

#include "core/passes/dummy_derivatives.h"

#include <gtest/gtest.h>

#include "core/flatten/flatten.h"
#include "core/passes/pantelides.h"
#include "tests/support/reduced_system.h"

namespace momenta {
namespace {

TEST(DummyDerivativesTest, CartesianPendulumGetsTwoStateSets) {
  testing::ReducedSystem r = testing::ReduceForPantelides(testing::kCartesianPendulum);
  DifferentiatedSystem differentiated = Pantelides(&r.sys);
  const std::vector<double> params = EvaluateParameters(*r.sys.flat, {});
  const size_t variables_before = r.sys.flat->variables.size();
  StateSelection selection = SelectDummyDerivatives(&r.sys, differentiated, params);
  EXPECT_EQ(
      selection.dummy_derivatives,
      (std::vector<std::string>{"der(pendulum.x)", "der(der(pendulum.x))", "der(pendulum.y)",
                                "der(der(pendulum.y))", "der(pendulum.vx)", "der(pendulum.vy)"}));
  EXPECT_TRUE(selection.new_states.empty());
  EXPECT_TRUE(selection.warnings.empty());
  // One choice per level: the positions, then the velocities, each chosen during the run.
  ASSERT_EQ(selection.choices.size(), 2u);
  for (const std::string& choice : selection.choices) {
    EXPECT_NE(choice.find("dynamic: one of {"), std::string::npos) << choice;
  }
  // Each dummy derivative is a variable of its own now, and each state set adds a state and
  // its selector.
  EXPECT_EQ(r.sys.flat->variables.size(), variables_before + 6 + 2 * 2);
  EXPECT_EQ(r.sys.flat->VariableName(VarId(r.Var("stateSet1.x"))), "stateSet1.x");
  EXPECT_EQ(r.sys.flat->VariableName(VarId(r.Var("stateSet2.x"))), "stateSet2.x");
}

}  // namespace
}  // namespace momenta
