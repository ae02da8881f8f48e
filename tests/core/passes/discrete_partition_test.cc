// The discrete partition: equations `k = expression` of discrete variables leave the continuous
// system for the event iteration, in the order their values depend on each other; a discrete
// variable that nothing sets, a loop among discrete variables and der() of one are the model's
// mistakes, reported by name.

#include "core/passes/discrete_partition.h"

#include <gtest/gtest.h>

#include "tests/support/reduced_system.h"
#include "tests/support/test_models.h"

namespace momenta {
namespace {

/// A model whose Integer variables j and k are set by equations, j from k: declared, and
/// written, in the order opposite to their dependency.
std::string Steps(const std::string& k_equation, const std::string& j_equation) {
  return R"(
model: Steps
variables:
  x: {start: 0, fixed: true}
  j: {type: Integer, start: 0}
  k: {type: Integer, start: 0}
equations:
  - der(x) = 1
  - )" + j_equation + R"(
  - )" + k_equation + R"(
experiment: {stop: 1, interval: 0.1}
outputs: [x, j]
)";
}

TEST(DiscretePartitionTest, DiscreteEquationsLeaveInDependencyOrder) {
  testing::ReducedSystem r = testing::Reduce(Steps("k = if x > 0.5 then 1 else 0", "j = k + 1"));
  const size_t equations_before = r.sys.equations.size();
  DiscreteStats stats;
  r.sys = PartitionDiscrete(std::move(r.sys), &stats);
  EXPECT_EQ(stats.variables, 2u);
  EXPECT_EQ(stats.equations, 2u);
  EXPECT_EQ(r.sys.equations.size(), equations_before - 2);
  ASSERT_EQ(r.sys.discrete.size(), 2u);
  EXPECT_EQ(r.sys.discrete[0].var.value(), r.Var("k"));  // j's value reads k's
  EXPECT_EQ(r.sys.discrete[1].var.value(), r.Var("j"));
}

TEST(DiscretePartitionTest, AModelWithoutDiscreteVariablesIsLeftAlone) {
  testing::ReducedSystem r = testing::Reduce(R"(
model: Decay
variables:
  x: {start: 1, fixed: true}
equations: [der(x) = -x]
)");
  const size_t equations_before = r.sys.equations.size();
  DiscreteStats stats;
  r.sys = PartitionDiscrete(std::move(r.sys), &stats);
  EXPECT_EQ(stats.variables, 0u);
  EXPECT_EQ(stats.equations, 0u);
  EXPECT_EQ(r.sys.equations.size(), equations_before);
  EXPECT_TRUE(r.sys.discrete.empty());
}

TEST(DiscretePartitionTest, ALoopAmongDiscreteVariablesIsNamed) {
  const std::string msg = testing::BuildError(Steps("k = j - 1", "j = k + 1"));
  EXPECT_NE(msg.find("the discrete variables"), std::string::npos) << msg;
  EXPECT_NE(msg.find(" j"), std::string::npos) << msg;
  EXPECT_NE(msg.find(" k"), std::string::npos) << msg;
  EXPECT_NE(msg.find("depend on each other at the same event; break the loop with pre()"),
            std::string::npos)
      << msg;
}

TEST(DiscretePartitionTest, ADiscreteVariableThatNothingSetsIsNamed) {
  const std::string msg = testing::BuildError(Steps("k*k = 4", "j = 2"));
  EXPECT_NE(msg.find("these discrete variables of Steps are set by no equation of the form "
                     "'x = expression' and by no when-clause:"),
            std::string::npos)
      << msg;
  EXPECT_NE(msg.find("\n    k"), std::string::npos) << msg;
}

}  // namespace
}  // namespace momenta
