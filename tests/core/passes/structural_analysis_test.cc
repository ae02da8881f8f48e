// Structural analysis: the matching of a regular model, and the messages for unbalanced,
// structurally singular and higher-index models, which must name the components, equations and
// variables involved (crafted with define: components).

#include "core/passes/structural_analysis.h"

#include <gtest/gtest.h>

#include "core/passes/alias_elimination.h"
#include "core/passes/index_reduction.h"
#include "tests/support/test_models.h"
#include "core/flatten/flatten.h"
#include "core/lang/yaml_loader.h"
#include "core/lang/builtin_library.h"

namespace momenta {
namespace {

using testing::BuildError;

std::string Between(const std::string& msg, const std::string& from, const std::string& to) {
  size_t a = msg.find(from);
  if (a == std::string::npos) return "";
  size_t b = msg.find(to, a + from.size());
  return msg.substr(a, b == std::string::npos ? std::string::npos : b - a);
}

TEST(StructuralAnalysisTest, RegularModelIsMatched) {
  ModelSpec spec = LoadModelString(R"(
model: Osc
components:
  wall: {type: Fixed}
  spring: {type: Spring, c: 4}
  m: {type: Mass, s: {start: 1, fixed: true}, v: {start: 0, fixed: true}}
connections:
  - [wall.flange, spring.flange_a]
  - [spring.flange_b, m.flange_a]
)", "test.yaml");
  auto flat = std::make_shared<FlatSystem>(Flatten(spec, BuiltinLibrary(), {}));
  AliasStats alias;
  IndexStats index;
  EquationSystem sys = ReduceIndex(EliminateAliases(MakeEquationSystem(flat), &alias), &index);
  Structure st = AnalyseStructure(sys);
  EXPECT_EQ(st.num_states, 2u);
  // A perfect matching: every equation determines one unknown and back.
  ASSERT_EQ(st.var_of_equation.size(), sys.equations.size());
  for (size_t k = 0; k < sys.equations.size(); ++k) {
    int32_t v = st.var_of_equation[k];
    ASSERT_GE(v, 0);
    EXPECT_EQ(st.equation_of_var[v], static_cast<int32_t>(k));
    EXPECT_EQ(sys.role[v], VarRole::kUnknown);
    // A state's equation holds its derivative; an algebraic variable's equation holds it.
    ExprPool& P = *sys.pool;
    ExprId leaf = st.is_state[v] ? P.Der(VarId(static_cast<uint32_t>(v))) : P.Var(VarId(static_cast<uint32_t>(v)));
    EXPECT_TRUE(ContainsLeaf(P, sys.equations[k].residual, leaf)) << flat->VariableName(VarId(v));
  }
  size_t states = 0;
  for (uint32_t v = 0; v < st.is_state.size(); ++v) {
    if (!st.is_state[v]) continue;
    ++states;
    EXPECT_TRUE(flat->VariableName(VarId(v)) == "m.s" || flat->VariableName(VarId(v)) == "m.v") << flat->VariableName(VarId(v));
  }
  EXPECT_EQ(states, 2u);
}

// Every component type is balanced on its own (flattening checks that); a model is unbalanced
// through what connects them: an open signal input, or the model's own variables and equations.

TEST(StructuralAnalysisTest, TooFewEquations) {
  // Half's input u is left open: x*x = u is one equation for h.x and h.u.
  std::string msg = BuildError(R"(
model: Short
define:
  Half:
    connectors: {u: RealInput}
    variables: {x: {}}
    equations:
      - x*x = u
components:
  h: {type: Half}
)");
  EXPECT_NE(msg.find("test.yaml: Short is unbalanced: 1 equation for 2 unknowns"), std::string::npos) << msg;
  std::string under = Between(msg, "Under-determined", "\n  which occur in");
  EXPECT_NE(under.find("h.x (Half, test.yaml:10:6)"), std::string::npos) << msg;
  EXPECT_NE(under.find("h.u (Half, test.yaml:10:6) — a signal input"), std::string::npos) << msg;
  EXPECT_NE(Between(msg, "which occur in", "\n  Over").find("h (Half, test.yaml:10:6): 'x*x = u'"),
            std::string::npos)
      << msg;
}

TEST(StructuralAnalysisTest, TooManyEquations) {
  // The model adds a second equation for t.x.
  std::string msg = BuildError(R"(
model: Long
define:
  Square:
    variables: {x: {}}
    equations:
      - x*x = 2
  Cube:
    variables: {z: {}}
    equations:
      - z^3 = 2
equations:
  - sin(t.x) = 0.5
components:
  t: {type: Square}
  f: {type: Cube}
)");
  EXPECT_NE(msg.find("Long is unbalanced: 3 equations for 2 unknowns"), std::string::npos) << msg;
  std::string over = Between(msg, "Over-determined", "Under-determined");
  EXPECT_NE(over.find("2 equations for only 1 unknown"), std::string::npos) << msg;
  EXPECT_NE(over.find("t (Square, test.yaml:15:6): 'x*x = 2'"), std::string::npos) << msg;
  EXPECT_NE(over.find("'sin(t.x) = 0.5' (test.yaml:13:5)"), std::string::npos) << msg;
  EXPECT_NE(over.find("t.x (Square, test.yaml:15:6)"), std::string::npos) << msg;
  // The well-determined part is not blamed.
  EXPECT_EQ(msg.find("z^3"), std::string::npos) << msg;
  EXPECT_EQ(msg.find("f.z"), std::string::npos) << msg;
}

TEST(StructuralAnalysisTest, StructurallySingular) {
  // Two equations for o.x and none for w: balanced in number, singular in structure.
  std::string msg = BuildError(R"(
model: Singular
define:
  Square:
    variables: {x: {}}
    equations:
      - x*x = 2
variables:
  w: {}
equations:
  - sin(o.x) = 0.5
components:
  o: {type: Square}
)");
  EXPECT_NE(msg.find("Singular is structurally singular"), std::string::npos) << msg;
  std::string over = Between(msg, "Over-determined", "Under-determined");
  EXPECT_NE(over.find("o (Square, test.yaml:13:6): 'x*x = 2'"), std::string::npos) << msg;
  EXPECT_NE(over.find("'sin(o.x) = 0.5'"), std::string::npos) << msg;
  EXPECT_NE(over.find("o.x (Square"), std::string::npos) << msg;
  std::string under = Between(msg, "Under-determined", "\n  Over");
  EXPECT_NE(under.find("\n    w"), std::string::npos) << msg;
  EXPECT_EQ(under.find("o.x"), std::string::npos) << msg;
}

TEST(StructuralAnalysisTest, UnconnectedSignalInput) {
  std::string msg = BuildError(R"(
model: Open
components:
  g: {type: Gain, k: 2}
  i: {type: Integrator}
connections:
  - [g.y, i.u]
)");
  EXPECT_NE(msg.find("unbalanced"), std::string::npos) << msg;
  EXPECT_NE(msg.find("g.u (Gain, test.yaml:4:6) — a signal input: connect it to an output"),
            std::string::npos)
      << msg;
}

TEST(StructuralAnalysisTest, LongListsAreCut) {
  // 20 open inputs: 40 unknowns for 20 equations; the list stops after 12.
  std::string msg = BuildError(R"(
model: Many
define:
  Open:
    connectors: {u: RealInput}
    variables: {x: {}}
    equations:
      - x*x = u
components:
  f: {type: Open, count: 20}
)");
  EXPECT_NE(msg.find("20 equations for 40 unknowns"), std::string::npos) << msg;
  std::string under = Between(msg, "Under-determined", "\n  which occur in");
  EXPECT_NE(under.find("f[1]."), std::string::npos) << msg;
  EXPECT_EQ(under.find("f[13]."), std::string::npos) << msg;
  EXPECT_NE(under.find("… and 28 more"), std::string::npos) << msg;
  EXPECT_NE(msg.find("… and 8 more"), std::string::npos) << msg;  // the 20 equations
}

}  // namespace
}  // namespace momenta
