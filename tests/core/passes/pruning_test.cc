// Pruning: what no output needs is dropped (an unprobed sensor, an independent subsystem) and
// named in the build report; what an output needs is kept together with the initial equations of
// the kept states.

#include "core/passes/pruning.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "core/passes/alias_elimination.h"
#include "core/passes/index_reduction.h"
#include "tests/support/test_models.h"
#include "core/flatten/flatten.h"
#include "core/lang/yaml_loader.h"
#include "core/lang/builtin_library.h"

namespace momenta {
namespace {

bool Has(const std::vector<std::string>& names, const std::string& name) {
  return std::find(names.begin(), names.end(), name) != names.end();
}

/// A mass pushed by a constant force, a kinetic-energy sensor on it, and an independent
/// oscillator; `outputs` decides what is kept.
std::string Model(const std::string& outputs) {
  return R"(
model: Prune
define:
  EnergySensor:
    parameters: {m: 1}
    connectors: {flange: Flange}
    variables: {v: {}, E: {}}
    equations:
      - v = der(flange.s)
      - E = 0.5*m*v^2
      - 0 = flange.f
components:
  m: {type: Mass, m: 2, s: {start: 0, fixed: true}, v: {start: 1, fixed: true}}
  push: {type: ConstantForce, f_constant: 4}
  energy: {type: EnergySensor, m: 2}
  wall: {type: Fixed}
  spring: {type: Spring, c: 1}
  osc: {type: Mass, m: 1, s: {start: 1, fixed: true}, v: {start: 0, fixed: true}}
connections:
  - [push.flange, m.flange_b]
  - [m.flange_a, energy.flange]
  - [wall.flange, spring.flange_a]
  - [spring.flange_b, osc.flange_a]
experiment: {stop: 1, interval: 0.25}
outputs: )" + outputs + "\n";
}

TEST(PruningTest, UnprobedSensorAndIndependentSubsystemArePruned) {
  testing::Built b = testing::BuildYaml(Model("[m.s]"));
  const auto& pruned = b.report.pruned;
  EXPECT_TRUE(Has(pruned, "energy.E")) << ::testing::PrintToString(pruned);
  EXPECT_TRUE(Has(pruned, "osc.s")) << ::testing::PrintToString(pruned);
  EXPECT_TRUE(Has(pruned, "osc.v")) << ::testing::PrintToString(pruned);
  EXPECT_FALSE(Has(pruned, "m.s"));
  EXPECT_FALSE(Has(pruned, "m.v"));
  // Only the pushed mass is integrated; its fixed starts are its initial equations, the
  // oscillator's are gone.
  EXPECT_EQ(b.model->num_states(), 2u);
  EXPECT_EQ(b.report.states, (std::vector<std::string>{"m.s", "m.v"}));
  bool m_start = false;
  for (const std::string& origin : b.model->initial_origin) {
    EXPECT_EQ(origin.find("osc."), std::string::npos) << origin;
    m_start = m_start || origin.find("fixed start value of m.s") != std::string::npos;
  }
  EXPECT_TRUE(m_start) << ::testing::PrintToString(b.model->initial_origin);
  EXPECT_EQ(b.model->initial_exprs.size(), 2u);
  // The pruning pass reports what it dropped.
  for (const auto& pass : b.report.passes) {
    if (pass.name == "pruning") EXPECT_NE(pass.note.find("not needed by the outputs"), std::string::npos);
  }
  // s = t + t^2 (v0 = 1, a = 4/2).
  testing::Trajectory tr = testing::RunDefault(b);
  for (size_t row = 0; row < tr.t.size(); ++row) {
    double t = tr.t[row];
    EXPECT_NEAR(tr.Column("m.s", row), t + t * t, 1e-6) << t;
  }
}

TEST(PruningTest, ProbedSensorIsKept) {
  testing::Built b = testing::BuildYaml(Model("[energy.E, osc.s]"));
  EXPECT_FALSE(Has(b.report.pruned, "energy.E"));
  EXPECT_FALSE(Has(b.report.pruned, "osc.s"));
  EXPECT_FALSE(Has(b.report.pruned, "osc.v"));
  // E needs m.v (not m.s: the push does not depend on position); osc.s needs both of osc's.
  EXPECT_TRUE(Has(b.report.pruned, "m.s"));
  EXPECT_EQ(b.model->num_states(), 3u);
  testing::Trajectory tr = testing::RunDefault(b);
  for (size_t row = 0; row < tr.t.size(); ++row) {
    double t = tr.t[row], v = 1 + 2 * t;
    EXPECT_NEAR(tr.Column("energy.E", row), 0.5 * 2 * v * v, 1e-5) << t;
    EXPECT_NEAR(tr.Column("osc.s", row), std::cos(t), 1e-5) << t;
  }
}

TEST(PruningTest, ThePrunePassKeepsTheClosureOfTheOutputs) {
  // The pass on its own: outputs [osc.s] need the oscillator's two states and nothing of m.
  ModelSpec spec = LoadModelString(Model("[osc.s]"), "test.yaml");
  auto flat = std::make_shared<FlatSystem>(Flatten(spec, BuiltinLibrary(), {}));
  EquationSystem sys = MakeEquationSystem(flat);
  AliasStats alias;
  IndexStats index;
  for (int round = 0; round < 3; ++round) {
    sys = EliminateAliases(std::move(sys), &alias);
    sys = ReduceIndex(std::move(sys), &index);
  }
  Structure st = AnalyseStructure(sys);
  const std::vector<VarRole> roles_before = sys.role;
  const size_t before = sys.num_unknowns(), equations_before = sys.equations.size();
  PruneStats stats;
  sys = Prune(std::move(sys), &st, &stats);
  EXPECT_EQ(sys.num_unknowns() + stats.variables, before);
  EXPECT_EQ(sys.equations.size() + stats.equations, equations_before);
  EXPECT_GT(stats.variables, 0u);
  // The matching stays consistent with the kept equations.
  ASSERT_EQ(st.var_of_equation.size(), sys.equations.size());
  for (size_t k = 0; k < sys.equations.size(); ++k) {
    int32_t v = st.var_of_equation[k];
    EXPECT_EQ(sys.role[v], VarRole::kUnknown);
    EXPECT_EQ(st.equation_of_var[v], static_cast<int32_t>(k));
  }
  for (uint32_t v = 0; v < sys.role.size(); ++v) {
    const std::string& name = flat->VariableName(VarId(v));
    if (roles_before[v] != VarRole::kUnknown) {
      EXPECT_EQ(sys.role[v], roles_before[v]) << name << ": only unknowns are pruned";
      continue;
    }
    if (name.rfind("m.", 0) == 0 || name.rfind("energy.", 0) == 0 || name.rfind("push.", 0) == 0) {
      EXPECT_EQ(sys.role[v], VarRole::kPruned) << name;
    }
  }
  for (const char* name : {"osc.s", "osc.v"}) {
    for (uint32_t v = 0; v < sys.role.size(); ++v) {
      if (flat->VariableName(VarId(v)) == name) EXPECT_EQ(sys.role[v], VarRole::kUnknown) << name;
    }
  }
  EXPECT_EQ(st.num_states, 2u);
  // The oscillator's two fixed starts are kept, the mass's two dropped.
  EXPECT_EQ(sys.initial.size(), 2u);
  EXPECT_EQ(stats.initial_equations, 2u);
}

TEST(PruningTest, InitialEquationsPullInWhatTheyNeed) {
  // The output needs x only; x's initial equation ties it to y, so y and its equation stay.
  testing::Built b = testing::BuildYaml(R"(
model: Tie
variables:
  x: {}
  y: {start: 2, fixed: true}
  z: {start: 0, fixed: true}
equations:
  - der(x) = -x
  - der(y) = -2*y
  - der(z) = 1
initial_equations:
  - x = y + 1
experiment: {stop: 1, interval: 0.5}
outputs: [x]
)");
  EXPECT_FALSE(Has(b.report.pruned, "y"));
  EXPECT_TRUE(Has(b.report.pruned, "z"));
  testing::Trajectory tr = testing::RunDefault(b);
  for (size_t row = 0; row < tr.t.size(); ++row) {
    EXPECT_NEAR(tr.Column("x", row), 3 * std::exp(-tr.t[row]), 1e-5) << tr.t[row];
  }
}

TEST(PruningTest, AFixedStartOfAVariableTheStatesDetermineIsKept) {
  // The output needs the state x only; tip = 2*x is not read, but its fixed start (an initial
  // equation that names no needed variable) settles x = 1.5 (x's own start, 0, is not fixed).
  // Pruned with tip, the initial equation was dropped and x started from 0.
  testing::Built b = testing::BuildYaml(R"(
model: Tip
variables:
  x: {start: 0}
  tip: {start: 3, fixed: true}
  z: {start: 0, fixed: true}
equations:
  - der(x) = -x
  - tip = 2*x
  - der(z) = 1
experiment: {stop: 1, interval: 0.5}
outputs: [x]
)");
  EXPECT_TRUE(Has(b.report.pruned, "z"));
  testing::Trajectory tr = testing::RunDefault(b);
  for (size_t row = 0; row < tr.t.size(); ++row) {
    EXPECT_NEAR(tr.Column("x", row), 1.5 * std::exp(-tr.t[row]), 1e-5) << tr.t[row];
  }
}

}  // namespace
}  // namespace momenta
