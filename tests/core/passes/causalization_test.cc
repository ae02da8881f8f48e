// Causalisation: explicit algebraic unknowns are inlined so that an RC ladder or a spring-damper
// chain leaves exactly its states for IDA; a nonlinear implicit equation and a true algebraic
// loop are kept for IDA and still simulate correctly.

#include "core/passes/causalization.h"

#include <gtest/gtest.h>

#include <cmath>

#include "tests/support/test_models.h"

namespace momenta {
namespace {

const PassReport* Pass(const BuildReport& r, const std::string& name) {
  for (const auto& p : r.passes) {
    if (p.name == name) return &p;
  }
  ADD_FAILURE() << "no pass " << name;
  return nullptr;
}

TEST(CausalizationTest, RcLadderLeavesOnlyItsStates) {
  for (double n : {1.0, 5.0, 10.0}) {
    testing::Built b = testing::BuildFile("models/rc_ladder.yaml", {{"n", n}});
    EXPECT_EQ(b.model->num_states(), static_cast<size_t>(n));
    EXPECT_EQ(b.model->num_unknowns(), b.model->num_states()) << "n = " << n;
    const PassReport* causal = Pass(b.report, "causalisation");
    ASSERT_TRUE(causal);
    EXPECT_EQ(causal->variables, static_cast<size_t>(n));
    EXPECT_NE(causal->note.find("0 algebraic loops"), std::string::npos) << causal->note;
    for (bool s : b.model->is_state) EXPECT_TRUE(s);
  }
}

TEST(CausalizationTest, SpringDamperChainLeavesTwoStatesPerMass) {
  testing::Built b = testing::BuildFile("models/spring_damper_chain.yaml", {{"n", 6}});
  EXPECT_EQ(b.model->num_states(), 12u);
  EXPECT_EQ(b.model->num_unknowns(), 12u);
  // Every residual is an ODE row: it holds its own unknown's derivative.
  for (size_t y = 0; y < b.model->num_unknowns(); ++y) {
    ExprId der = b.model->pool->Der(b.model->unknowns[y]);
    EXPECT_TRUE(ContainsLeaf(*b.model->pool, b.model->residual_exprs[y], der))
        << b.model->flat->VariableName(VarId(b.model->unknowns[y].value()));
  }
}

TEST(CausalizationTest, ChainOfExplicitEquationsIsInlinedInDependencyOrder) {
  // c needs b, b needs a, a needs the state: all inlined, whatever order they are written in.
  testing::Built b = testing::BuildYaml(R"(
model: Chain
parameters:
  k: 3
variables:
  c: {}
  b: {}
  a: {}
  s: {start: 1, fixed: true}
equations:
  - c = b + a
  - k*b = 2*a
  - a = sin(s) + time
  - der(s) = -c
experiment: {stop: 1, interval: 0.5}
outputs: [c, s]
)");
  EXPECT_EQ(b.model->num_unknowns(), 1u);
  const PassReport* causal = Pass(b.report, "causalisation");
  ASSERT_TRUE(causal);
  EXPECT_NE(causal->note.find("3 solved explicitly"), std::string::npos) << causal->note;
  // b was solved with the parameter coefficient k, which is guarded against zero.
  EXPECT_EQ(b.model->guards.size(), 1u);
  EXPECT_NE(testing::BuildError(R"(
model: Chain
parameters:
  k: 3
variables:
  c: {}
  b: {}
  a: {}
  s: {start: 1, fixed: true}
equations:
  - c = b + a
  - k*b = 2*a
  - a = sin(s) + time
  - der(s) = -c
outputs: [c]
)", {{"k", 0}}).find("cannot be solved for b"), std::string::npos);
  // c = (2/3 + 1) a with a = sin(s) + t.
  testing::Trajectory tr = testing::RunDefault(b);
  for (size_t row = 0; row < tr.t.size(); ++row) {
    double a = std::sin(tr.Column("s", row)) + tr.t[row];
    EXPECT_NEAR(tr.Column("c", row), (2.0 / 3 + 1) * a, 1e-9) << tr.t[row];
  }
}

TEST(CausalizationTest, NonlinearImplicitEquationIsKeptForIda) {
  // x + exp(x) = u cannot be solved for x explicitly: x stays an algebraic unknown.
  testing::Built b = testing::BuildYaml(R"(
model: Implicit
variables:
  u: {}
  x: {start: 0}
  s: {start: 0, fixed: true}
equations:
  - u = 1 + time
  - x + exp(x) = u
  - der(s) = x
experiment: {stop: 2, interval: 0.25, tolerance: 1e-8}
outputs: [x, u, s]
)");
  EXPECT_EQ(b.model->num_unknowns(), 2u);
  EXPECT_EQ(b.model->num_states(), 1u);
  testing::Trajectory tr = testing::RunDefault(b);
  ASSERT_EQ(tr.t.size(), 9u);
  for (size_t row = 0; row < tr.t.size(); ++row) {
    double x = tr.Column("x", row), u = tr.Column("u", row);
    EXPECT_NEAR(u, 1 + tr.t[row], 1e-12);
    EXPECT_NEAR(x + std::exp(x), u, 1e-6) << tr.t[row];
  }
  // x(0) = 0 (0 + e^0 = 1) and x grows with u.
  EXPECT_NEAR(tr.Column("x", 0), 0.0, 1e-6);
  EXPECT_GT(tr.Column("x", 8), tr.Column("x", 4));
}

// A Real defined by its own left limit holds its value until b turns true (a sample-and-hold).
// Inlined, its solution would replace pre(y) by itself: the build looped until memory ran out.
TEST(CausalizationTest, RealDefinedByItsOwnPreValueIsKeptAnUnknown) {
  testing::Built b = testing::BuildYaml(R"(
model: Hold
variables:
  x: {start: 0, fixed: true}
  y: {start: 1}
  b: {type: Boolean, start: false}
equations:
  - der(x) = 1
  - b = x > 0.5
  - y = if b then 4 else pre(y)
experiment: {stop: 1, interval: 0.1}
outputs: [x, y]
)");
  EXPECT_EQ(b.model->num_unknowns(), 2u);  // x, and y kept
  testing::Trajectory tr = testing::RunDefault(b);
  for (size_t row = 0; row < tr.t.size(); ++row) {
    // Rows up to the event at x = 0.5 (its left limit included) hold the start value.
    const bool after = tr.t[row] > 0.5 + 1e-6 || (row > 0 && tr.t[row] == tr.t[row - 1]);
    EXPECT_EQ(tr.Column("y", row), after ? 4.0 : 1.0) << "t = " << tr.t[row];
  }
}

TEST(CausalizationTest, AlgebraicLoopIsKeptForIda) {
  // x needs y and y needs x: each equation is linear in its own unknown, but they form a loop.
  testing::Built b = testing::BuildYaml(R"(
model: Loop
variables:
  x: {start: 1}
  y: {start: 1}
  s: {start: 0, fixed: true}
equations:
  - x + y^3 = 2 + time
  - y = x^3
  - der(s) = x + y
experiment: {stop: 1, interval: 0.25, tolerance: 1e-8}
outputs: [x, y, s]
)");
  const PassReport* causal = Pass(b.report, "causalisation");
  ASSERT_TRUE(causal);
  EXPECT_NE(causal->note.find("1 algebraic loops (2 unknowns)"), std::string::npos) << causal->note;
  EXPECT_EQ(b.model->num_unknowns(), 3u);
  testing::Trajectory tr = testing::RunDefault(b);
  for (size_t row = 0; row < tr.t.size(); ++row) {
    double x = tr.Column("x", row), y = tr.Column("y", row);
    EXPECT_NEAR(y, x * x * x, 1e-6) << tr.t[row];
    EXPECT_NEAR(x + y * y * y, 2 + tr.t[row], 1e-6) << tr.t[row];
  }
  EXPECT_NEAR(tr.Column("x", 0), 1.0, 1e-6);
}

TEST(CausalizationTest, ResistorsInParallelAreInlinedOrKeptButCorrect) {
  // A current source drives two resistors in parallel: whatever is inlined, the voltage is
  // I*R1*R2/(R1 + R2) and the currents split in inverse proportion.
  testing::Built b = testing::BuildYaml(R"(
model: Parallel
components:
  ground: {type: Ground}
  src: {type: CurrentSource}
  level: {type: Constant, k: 3}
  r1: {type: Resistor, R: 2}
  r2: {type: Resistor, R: 4}
  c: {type: Capacitor, C: 1, v: {start: 0, fixed: true}}
connections:
  - [level.y, src.i]
  - [src.n, r1.p]
  - [r1.p, r2.p]
  - [r1.n, r2.n]
  - [r2.n, ground.p]
  - [src.p, ground.p]
  - [c.p, r1.p]
  - [c.n, ground.p]
experiment: {stop: 1, interval: 0.5}
outputs: [r1.v, r1.i, r2.i, c.v]
)");
  // Only the capacitor's voltage is left for IDA.
  EXPECT_EQ(b.model->num_unknowns(), 1u);
  testing::Trajectory tr = testing::RunDefault(b);
  // The capacitor charges through the parallel 4/3 Ohm: v = 4(1 - exp(-t/(4/3))).
  for (size_t row = 0; row < tr.t.size(); ++row) {
    double t = tr.t[row], v = 4 * (1 - std::exp(-t * 3 / 4));
    EXPECT_NEAR(tr.Column("c.v", row), v, 1e-5) << t;
    EXPECT_NEAR(tr.Column("r1.v", row), v, 1e-5) << t;
    EXPECT_NEAR(tr.Column("r1.i", row), v / 2, 1e-5) << t;
    EXPECT_NEAR(tr.Column("r2.i", row), v / 4, 1e-5) << t;
  }
}

}  // namespace
}  // namespace momenta
