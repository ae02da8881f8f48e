// Alias elimination: sign aliases, offsets, constants, chains, which variable of an alias set
// stays, and a chain of rods that collapses to the mass it hangs from with the right offset.

#include "core/passes/alias_elimination.h"

#include <gtest/gtest.h>

#include <cmath>

#include "core/passes/conditional_connectors.h"
#include "core/expr/expr_eval.h"
#include "core/passes/structural_conditions.h"
#include "tests/support/test_models.h"
#include "core/flatten/flatten.h"
#include "core/lang/yaml_loader.h"
#include "core/lang/builtin_library.h"

namespace momenta {
namespace {

/// A flat system written by hand: named variables and residuals.
class HandSystem {
 public:
  HandSystem() : flat_(std::make_shared<FlatSystem>()) {
    flat_->pool = std::make_shared<ExprPool>();
    flat_->file = "hand.yaml";
    flat_->model_name = "Hand";
  }
  ExprPool& pool() { return *flat_->pool; }
  ExprId Var(const std::string& name, int priority = 0, bool flow = false) {
    FlatVariable v;
    v.name = flat_->Own(name);
    v.state_priority = priority;
    v.is_flow = flow;
    flat_->variables.push_back(v);
    return pool().Var(VarId(flat_->variables.size() - 1));
  }
  ExprId Param(const std::string& name, double value) {
    FlatParameter p;
    p.name = flat_->Own(name);
    p.binding = pool().Const(value);
    flat_->parameters.push_back(p);
    flat_->parameter_order.push_back(ParamId(flat_->parameters.size() - 1));
    return pool().Param(ParamId(flat_->parameters.size() - 1));
  }
  void Eq(ExprId lhs, ExprId rhs, const std::string& text) {
    FlatEquation e;
    e.residual = pool().Sub(lhs, rhs);
    e.origin = EquationOrigin::kModel;
    e.text = flat_->Own(text);
    flat_->equations.push_back(e);
  }
  void Output(ExprId e, const std::string& text) { flat_->outputs.push_back({text, e, {}}); }
  FlatVariable& var(ExprId v) { return flat_->variables[pool().node(v).a]; }
  EquationSystem Eliminate(AliasStats* stats) {
    return EliminateAliases(MakeEquationSystem(flat_), stats);
  }
  std::shared_ptr<FlatSystem> flat_;
};

uint32_t Index(const ExprPool& pool, ExprId v) { return pool.node(v).a; }

TEST(AliasEliminationTest, SignAlias) {
  // Two flows of a connection set: a + b = 0.
  HandSystem h;
  ExprId a = h.Var("a", 0, true), b = h.Var("b", 0, true), c = h.Var("c");
  h.Eq(h.pool().Add(a, b), h.pool().Zero(), "a + b = 0");
  h.Eq(h.pool().Mul(c, c), b, "c*c = b");
  AliasStats stats;
  EquationSystem sys = h.Eliminate(&stats);
  EXPECT_EQ(stats.aliases, 1u);
  EXPECT_EQ(stats.constants, 0u);
  ASSERT_EQ(sys.equations.size(), 1u);
  // The later-declared b goes; a stays.
  EXPECT_EQ(sys.role[Index(h.pool(), a)], VarRole::kUnknown);
  EXPECT_EQ(sys.role[Index(h.pool(), b)], VarRole::kAlias);
  EXPECT_EQ(sys.eliminated->Apply(b), h.pool().Neg(a));
  // The remaining equation now reads c*c = -a.
  EXPECT_EQ(sys.equations[0].residual, h.pool().Sub(h.pool().Mul(c, c), h.pool().Neg(a)));
  EXPECT_EQ(sys.num_unknowns(), 2u);
}

TEST(AliasEliminationTest, OffsetAndScaledAliases) {
  HandSystem h;
  ExprPool& P = h.pool();
  ExprId L = h.Param("L", 0.5);
  ExprId a = h.Var("a"), b = h.Var("b"), c = h.Var("c");
  h.Eq(b, P.Add(a, P.Div(L, P.Const(2))), "b = a + L/2");
  // 2c = -2b + 3: still an alias (equal magnitudes).
  h.Eq(P.Mul(P.Const(2), c), P.Add(P.Mul(P.Const(-2), b), P.Const(3)), "2*c = -2*b + 3");
  h.Output(c, "c");
  AliasStats stats;
  EquationSystem sys = h.Eliminate(&stats);
  EXPECT_EQ(stats.aliases, 2u);
  EXPECT_TRUE(sys.equations.empty());
  EXPECT_EQ(sys.num_unknowns(), 1u);
  // c = -(a + 0.25) + 1.5, in terms of a.
  std::vector<double> params = {0.5}, vars = {2.0, 0, 0};
  LeafValues lv;
  lv.params = params.data();
  lv.vars = vars.data();
  ExprId cx = sys.eliminated->Apply(c);
  EXPECT_TRUE(ContainsLeaf(P, cx, a));
  EXPECT_FALSE(ContainsLeaf(P, cx, b));
  EXPECT_DOUBLE_EQ(Evaluate(P, cx, lv), -(2.0 + 0.25) + 1.5);
  // The output was rewritten too.
  EXPECT_EQ(sys.outputs[0], cx);
}

TEST(AliasEliminationTest, UnequalCoefficientsAreNotAliases) {
  HandSystem h;
  ExprPool& P = h.pool();
  ExprId a = h.Var("a"), b = h.Var("b"), c = h.Var("c");
  h.Eq(a, P.Mul(P.Const(2), b), "a = 2*b");
  h.Eq(P.Add(a, b), c, "a + b = c");
  h.Eq(P.Mul(a, b), P.Const(1), "a*b = 1");
  h.Eq(a, P.Time(), "a = time");
  AliasStats stats;
  EquationSystem sys = h.Eliminate(&stats);
  EXPECT_EQ(stats.aliases + stats.constants, 0u);
  EXPECT_EQ(sys.equations.size(), 4u);
  EXPECT_EQ(sys.num_unknowns(), 3u);
}

TEST(AliasEliminationTest, Constants) {
  HandSystem h;
  ExprPool& P = h.pool();
  ExprId s0 = h.Param("s0", 1.25);
  ExprId a = h.Var("a"), b = h.Var("b"), c = h.Var("c"), d = h.Var("d");
  h.Eq(a, s0, "a = s0");                        // a Fixed flange
  h.Eq(b, P.Sub(a, P.Const(2)), "b = a - 2");    // an alias of a constant is a constant
  h.Eq(P.Mul(P.Const(4), c), P.Const(2), "4*c = 2");
  h.Eq(P.Mul(d, d), P.Add(b, c), "d*d = b + c");
  AliasStats stats;
  EquationSystem sys = h.Eliminate(&stats);
  EXPECT_EQ(stats.constants, 3u);
  EXPECT_EQ(stats.aliases, 0u);
  for (ExprId v : {a, b, c}) EXPECT_EQ(sys.role[Index(P, v)], VarRole::kConstant);
  EXPECT_EQ(sys.role[Index(P, d)], VarRole::kUnknown);
  std::vector<double> params = {1.25};
  LeafValues lv;
  lv.params = params.data();
  for (auto [v, want] : {std::pair{a, 1.25}, std::pair{b, -0.75}, std::pair{c, 0.5}}) {
    ExprId e = sys.eliminated->Apply(v);
    EXPECT_TRUE(P.IsParamOnly(e));
    EXPECT_DOUBLE_EQ(Evaluate(P, e, lv), want);
  }
  ASSERT_EQ(sys.equations.size(), 1u);
  EXPECT_FALSE(ContainsLeaf(P, sys.equations[0].residual, b));
}

TEST(AliasEliminationTest, AnAliasThatAppearsInALaterScan) {
  // x + y + z = 0 has three roots when first met; z = 5, listed after it, makes z a constant,
  // so the next scan finds x + y + 5 = 0: an alias. The equation that can never be one (not
  // affine) is skipped by the later scans and rewritten at the end like any other.
  HandSystem h;
  ExprPool& P = h.pool();
  ExprId x = h.Var("x"), y = h.Var("y"), z = h.Var("z"), w = h.Var("w");
  h.Eq(P.Add(P.Add(x, y), z), P.Const(0), "x + y + z = 0");
  h.Eq(P.Mul(w, w), y, "w*w = y");
  h.Eq(z, P.Const(5), "z = 5");
  AliasStats stats;
  EquationSystem sys = h.Eliminate(&stats);
  EXPECT_EQ(stats.constants, 1u);
  EXPECT_EQ(stats.aliases, 1u);
  EXPECT_EQ(sys.role[Index(P, x)], VarRole::kUnknown);  // declared first: x stays
  EXPECT_EQ(sys.role[Index(P, y)], VarRole::kAlias);
  ASSERT_EQ(sys.equations.size(), 1u);
  // w*w - y with y = -x - 5: at x = 2, w = 3 it is 9 + 7.
  EXPECT_FALSE(ContainsLeaf(P, sys.equations[0].residual, y));
  std::vector<double> vars = {2, 0, 0, 3};
  LeafValues lv;
  lv.vars = vars.data();
  EXPECT_DOUBLE_EQ(Evaluate(P, sys.equations[0].residual, lv), 16);
  // A second round finds nothing new and leaves the system as it was.
  const ExprId residual = sys.equations[0].residual;
  const size_t nodes = P.size();
  sys = EliminateAliases(std::move(sys), &stats);
  EXPECT_EQ(stats.aliases + stats.constants, 2u);
  ASSERT_EQ(sys.equations.size(), 1u);
  EXPECT_EQ(sys.equations[0].residual, residual);
  EXPECT_EQ(P.size(), nodes);
}

TEST(AliasEliminationTest, RedundantAndContradictoryEquationsStay) {
  // They are for the structural analysis to report, not to vanish.
  HandSystem h;
  ExprPool& P = h.pool();
  ExprId a = h.Var("a"), b = h.Var("b"), c = h.Var("c");
  h.Eq(a, b, "a = b");
  h.Eq(b, a, "b = a");
  h.Eq(c, P.Const(1), "c = 1");
  h.Eq(c, P.Const(2), "c = 2");
  AliasStats stats;
  EquationSystem sys = h.Eliminate(&stats);
  EXPECT_EQ(stats.aliases, 1u);
  EXPECT_EQ(stats.constants, 1u);
  EXPECT_EQ(sys.equations.size(), 2u);
}

TEST(AliasEliminationTest, ChainsResolveToOneRoot) {
  HandSystem h;
  ExprPool& P = h.pool();
  ExprId p = h.Param("p", 3);
  std::vector<ExprId> x;
  for (int k = 0; k < 6; ++k) x.push_back(h.Var("x" + std::to_string(k)));
  // Listed out of order, with signs and offsets: x1 = x0, x2 = -x1 + 1, x3 = x2 + p, x4 = -x3,
  // x5 = x4 - x0... (x5 - x4 = 0 written as x4 = x5).
  h.Eq(x[3], P.Add(x[2], p), "x3 = x2 + p");
  h.Eq(x[4], P.Neg(x[3]), "x4 = -x3");
  h.Eq(x[1], x[0], "x1 = x0");
  h.Eq(x[2], P.Add(P.Neg(x[1]), P.Const(1)), "x2 = -x1 + 1");
  h.Eq(x[4], x[5], "x4 = x5");
  AliasStats stats;
  EquationSystem sys = h.Eliminate(&stats);
  EXPECT_EQ(stats.aliases, 5u);
  EXPECT_EQ(sys.num_unknowns(), 1u);
  // The first declared stays.
  EXPECT_EQ(sys.role[Index(P, x[0])], VarRole::kUnknown);
  std::vector<double> params = {3}, vars = {0.75, 0, 0, 0, 0, 0};
  LeafValues lv;
  lv.params = params.data();
  lv.vars = vars.data();
  const double x0 = 0.75, x1 = x0, x2 = -x1 + 1, x3 = x2 + 3, x4 = -x3, x5 = x4;
  const double want[] = {x0, x1, x2, x3, x4, x5};
  for (int k = 0; k < 6; ++k) {
    ExprId e = sys.eliminated->Apply(x[k]);
    EXPECT_EQ(CollectLeaves(P, e, kHasVar), std::vector<ExprId>{x[0]}) << k;
    EXPECT_DOUBLE_EQ(Evaluate(P, e, lv), want[k]) << "x" << k;
  }
}

TEST(AliasEliminationTest, TheDifferentiatedVariableStays) {
  // a = b with der(b) appearing: b stays although a is declared first.
  HandSystem h;
  ExprPool& P = h.pool();
  ExprId a = h.Var("a"), b = h.Var("b"), v = h.Var("v");
  h.Eq(a, b, "a = b");
  h.Eq(v, P.Der(VarId(1u)), "v = der(b)");
  h.Eq(P.Der(VarId(2u)), P.Neg(a), "der(v) = -a");
  AliasStats stats;
  EquationSystem sys = h.Eliminate(&stats);
  EXPECT_EQ(sys.role[Index(P, a)], VarRole::kAlias);
  EXPECT_EQ(sys.role[Index(P, b)], VarRole::kUnknown);
  EXPECT_EQ(sys.eliminated->Apply(a), b);
}

TEST(AliasEliminationTest, PreferredStatesAndNonFlowsStay) {
  HandSystem h;
  ExprPool& P = h.pool();
  ExprId a = h.Var("a"), b = h.Var("b", /*priority=*/1);
  ExprId f = h.Var("f", 0, /*flow=*/true), g = h.Var("g");
  h.Eq(a, b, "a = b");
  h.Eq(f, P.Neg(g), "f = -g");
  AliasStats stats;
  EquationSystem sys = h.Eliminate(&stats);
  EXPECT_EQ(sys.role[Index(P, a)], VarRole::kAlias);
  EXPECT_EQ(sys.role[Index(P, b)], VarRole::kUnknown);
  EXPECT_EQ(sys.role[Index(P, f)], VarRole::kAlias);
  EXPECT_EQ(sys.role[Index(P, g)], VarRole::kUnknown);
  EXPECT_EQ(sys.eliminated->Apply(f), P.Neg(g));
}

TEST(AliasEliminationTest, DerivativesAndStartValuesFollowTheRoot) {
  HandSystem h;
  ExprPool& P = h.pool();
  ExprId a = h.Var("a"), b = h.Var("b"), c = h.Var("c");
  h.var(b).start = P.Const(2);
  // b = -a + 1, and both are differentiated: a (first) stays; der(b) becomes -der(a).
  h.Eq(b, P.Add(P.Neg(a), P.Const(1)), "b = -a + 1");
  h.Eq(P.Der(VarId(0u)), c, "der(a) = c");
  h.Eq(P.Der(VarId(1u)), P.Mul(c, c), "der(b) = c*c");
  AliasStats stats;
  EquationSystem sys = h.Eliminate(&stats);
  EXPECT_EQ(sys.role[Index(P, b)], VarRole::kAlias);
  ASSERT_EQ(sys.equations.size(), 2u);
  EXPECT_EQ(sys.equations[1].residual, P.Sub(P.Neg(P.Der(VarId(0u))), P.Mul(c, c)));
  // a had no start value: it takes b's, solved back: a = -(2 - 1).
  EXPECT_TRUE(P.IsConst(sys.guess[Index(P, a)], -1.0)) << P.ConstValue(sys.guess[Index(P, a)]);
}

TEST(AliasEliminationTest, ChainOfRodsCollapsesWithTheRightOffset) {
  // A mass (L = 0.2) pushes a chain of n massless rods (L = 0.5 each) at v = 1 m/s. Every rod
  // flange is an alias of the mass's position: the far end is mass.s + 0.1 + 0.5*n.
  const int n = 2000;
  const std::string yaml = R"(
model: Rods
parameters:
  n: )" + std::to_string(n) + R"(
components:
  m: {type: Mass, m: 2, L: 0.2, s: {start: 0, fixed: true}, v: {start: 1, fixed: true}}
  rod: {type: Rod, count: n, L: 0.5}
connections:
  - [m.flange_b, "rod[1].flange_a"]
  - for: i in 1:n-1
    connect: ["rod[i].flange_b", "rod[i+1].flange_a"]
experiment: {stop: 1, interval: 0.5}
outputs: ["rod[n].flange_b.s", "rod[1].flange_a.f"]
)";
  // The pass on its own: the output is m.s plus a parameter offset.
  {
    ModelSpec spec = LoadModelString(yaml, "test.yaml");
    auto flat = std::make_shared<FlatSystem>(Flatten(spec, BuiltinLibrary(), {}));
    std::vector<double> params = EvaluateParameters(*flat, {});
    AliasStats stats;
    EquationSystem sys = EliminateAliases(MakeEquationSystem(flat), &stats);
    EXPECT_EQ(sys.num_unknowns(), 3u);  // m.s, m.v, m.a
    ExprPool& P = *sys.pool;
    uint32_t ms = 0;
    for (uint32_t k = 0; k < flat->variables.size(); ++k) {
      if (flat->VariableName(VarId(k)) == "m.s") ms = k;
    }
    EXPECT_EQ(CollectLeaves(P, sys.outputs[0], kHasVar), std::vector<ExprId>{P.Var(VarId(ms))});
    AffineForm form;
    ASSERT_TRUE(DecomposeAffine(&P, sys.outputs[0], 2, &form));
    ASSERT_EQ(form.terms.size(), 1u);
    EXPECT_EQ(form.terms[0].second, 1.0);
    // The offset is a chain of n parameter additions; evaluate it through a compiled-free path:
    // its parameters are all 0.5 (rods) and 0.2 (mass).
    std::vector<double> vars(flat->variables.size(), 0.0);
    LeafValues lv;
    lv.params = params.data();
    lv.vars = vars.data();
    EXPECT_NEAR(Evaluate(P, form.offset, lv), 0.1 + 0.5 * n, 1e-9);
    // The rod's flows are constants (the far end is free).
    EXPECT_TRUE(P.IsConst(sys.outputs[1], 0.0));
    EXPECT_GE(stats.aliases, static_cast<size_t>(2 * n));
  }
  // The whole pipeline, simulated.
  testing::Built b = testing::BuildYaml(yaml);
  EXPECT_EQ(b.model->num_unknowns(), 2u);
  testing::Trajectory tr = testing::RunDefault(b);
  ASSERT_EQ(tr.t.size(), 3u);
  for (size_t row = 0; row < tr.t.size(); ++row) {
    EXPECT_NEAR(tr.Column("rod[n].flange_b.s", row), tr.t[row] + 0.1 + 0.5 * n, 1e-6) << tr.t[row];
    EXPECT_EQ(tr.Column("rod[1].flange_a.f", row), 0.0);
  }
}

TEST(AliasEliminationTest, FixedFlangeGivesConstants) {
  // A Fixed at s0 = 2 holds a spring whose other end a mass pulls: the Fixed's flange and the
  // spring's flange_a are constants, not unknowns.
  const char* yaml = R"(
model: Hang
components:
  wall: {type: Fixed, s0: 2}
  spring: {type: Spring, c: 4, s_rel0: 1}
  m: {type: Mass, m: 1, s: {start: 3.5, fixed: true}, v: {start: 0, fixed: true}}
connections:
  - [wall.flange, spring.flange_a]
  - [spring.flange_b, m.flange_a]
experiment: {stop: 1, interval: 0.25}
outputs: [m.s, spring.flange_a.s, wall.flange.f]
)";
  ModelSpec spec = LoadModelString(yaml, "test.yaml");
  auto flat = std::make_shared<FlatSystem>(Flatten(spec, BuiltinLibrary(), {}));
  AliasStats stats;
  EquationSystem sys = EliminateAliases(MakeEquationSystem(flat), &stats);
  EXPECT_GE(stats.constants, 2u);
  for (uint32_t k = 0; k < flat->variables.size(); ++k) {
    const std::string& name = flat->VariableName(VarId(k));
    if (name == "wall.flange.s" || name == "spring.flange_a.s") {
      EXPECT_EQ(sys.role[k], VarRole::kConstant) << name;
    }
  }
  EXPECT_TRUE(sys.pool->IsParamOnly(sys.outputs[1]));
  // Simulated: s(t) = 3 + 0.5*cos(2t) about the rest position wall + s_rel0 = 3.
  testing::Built b = testing::BuildYaml(yaml);
  testing::Trajectory tr = testing::RunDefault(b);
  for (size_t row = 0; row < tr.t.size(); ++row) {
    double t = tr.t[row];
    EXPECT_NEAR(tr.Column("m.s", row), 3 + 0.5 * std::cos(2 * t), 1e-4) << t;
    EXPECT_EQ(tr.Column("spring.flange_a.s", row), 2.0);
    // The wall holds the spring: its flange force balances the spring force c*(s_rel - 1).
    EXPECT_NEAR(tr.Column("wall.flange.f", row), 4 * (tr.Column("m.s", row) - 2 - 1), 1e-4) << t;
  }
}

/// An expression, exactly: every node's operation and operands, constants in hexadecimal, leaves
/// by kind and index (a pool's node ids do not show).
std::string Exact(const ExprPool& pool, ExprId e) {
  const Node& n = pool.node(e);
  char buf[64];
  if (n.op == Op::kConst) {
    std::snprintf(buf, sizeof buf, "%a", n.value());
    return buf;
  }
  if (IsLeaf(n.op)) {
    std::snprintf(buf, sizeof buf, "L%d.%u.%u", static_cast<int>(n.op), n.a, n.b);
    return buf;
  }
  std::string out = "(" + std::to_string(static_cast<int>(n.op));
  const int arity = Arity(n.op);
  if (arity >= 1) out += " " + Exact(pool, ExprId(n.a));
  if (arity >= 2) out += " " + Exact(pool, ExprId(n.b));
  if (arity >= 3) out += " " + Exact(pool, ExprId(n.c));
  return out + ")";
}

/// What the first alias elimination leaves of a model, exactly: every equation, output, role and
/// start guess, and the counts; `deferred` says whether flattening left the sure aliases unmade
/// (as the build does), `*unmade` how many it left.
std::string AfterFirstAliasElimination(const ModelSpec& spec, bool deferred, size_t* unmade) {
  auto flat = std::make_shared<FlatSystem>(Flatten(spec, BuiltinLibrary(), {}, deferred));
  *unmade = 0;
  for (const FlatEquation& eq : flat->equations) *unmade += eq.residual.valid() ? 0 : 1;
  std::shared_ptr<const DeferredEquations> later = std::move(flat->deferred);
  const std::vector<double> params = EvaluateParameters(*flat, {});
  EquationSystem sys = MakeEquationSystem(flat);
  FoldStructuralConditions(&sys, params);
  ResolveConditionalConnectors(&sys, params);
  AliasStats stats;
  sys = EliminateAliases(std::move(sys), &stats, later.get());
  const ExprPool& p = *sys.pool;
  std::string text = std::to_string(stats.aliases) + " aliases, " + std::to_string(stats.constants) + " constants\n";
  for (const SystemEquation& eq : sys.equations) text += Exact(p, eq.residual) + "\n";
  for (ExprId o : sys.outputs) text += "output " + Exact(p, o) + "\n";
  for (size_t v = 0; v < sys.role.size(); ++v) {
    text += std::to_string(static_cast<int>(sys.role[v])) + " " + Exact(p, sys.guess[v]) + "\n";
  }
  return text;
}

/// Checks that leaving the sure aliases unmade changes nothing on `spec`; returns how many were.
size_t ExpectTheSameSystem(const ModelSpec& spec) {
  size_t made_unmade = 0, unmade = 0;
  const std::string made = AfterFirstAliasElimination(spec, false, &made_unmade);
  const std::string later = AfterFirstAliasElimination(spec, true, &unmade);
  EXPECT_EQ(made_unmade, 0u) << spec.file;
  EXPECT_EQ(made, later) << spec.file;
  return unmade;
}

TEST(AliasEliminationTest, EquationsNotMadeGiveTheSameSystem) {
  // The build does not make the equations alias elimination surely removes (a flow equal to a
  // force, a connection between two variables, an unconnected flow): it reads their forms. What
  // the pass leaves must be what it leaves of the made equations, node for node, on models with
  // conditional connectors (the chain's and the friction models' heat ports), Boolean
  // connections, flow sets of three, impacts, arrays and composite types.
  for (const char* file : {"models/spring_damper_chain.yaml", "models/msl/Friction.yaml", "models/msl/Logical.yaml",
                           "models/msl/HeatLosses.yaml", "models/staircase.yaml", "models/carrier_collision_maplesim.yaml",
                           "models/slider_crank.yaml", "models/rc_ladder.yaml", "models/ball_pendulum.yaml"}) {
    EXPECT_GT(ExpectTheSameSystem(LoadModelFile(testing::SourcePath(file))), 0u) << file;
  }
}

TEST(AliasEliminationTest, EquationsWhoseFormDependsOnFoldingOrderAreMade) {
  // Several constants, or a variable named twice, are folded in an order that follows node ids:
  // such a template is made (its offset could differ in the last bit: 2.5 against
  // 2.5000000000000004 here), and the system is the same.
  const ModelSpec spec = LoadModelString(R"(
model: Folding
define:
  T:
    variables:
      x: {start: 0, fixed: true}
      z1: {}
      z2: {}
      z3: {}
    equations:
      - der(x) = z1 + z2 + z3
      - z1 = 2.2 - x - 2.2
      - z2 = 2.2 - x + 0.2 + 0.35 - 0.1 - 0.15
      - z3 = x + x - x
components:
  A: {type: T}
  B: {type: T}
experiment: {stop: 1}
outputs: [A.x, B.x]
)", "folding.yaml");
  EXPECT_EQ(ExpectTheSameSystem(spec), 0u);
}

TEST(AliasEliminationTest, AVariableAModelWhenClauseAssignsIsNotAliasedAway) {
  // K.w is discrete because the model's when-clause assigns it, which flattening learns after
  // the components: the component's v = w is then made (discrete variables are never aliased).
  const char* yaml = R"(
model: WhenInput
define:
  Sink:
    connectors:
      w: {type: RealInput}
    variables:
      v: {}
      x: {start: 0, fixed: true}
    equations:
      - v = w
      - der(x) = v
components:
  K: {type: Sink}
when:
  - when: time > 0.5
    then: ["K.w = 2"]
experiment: {stop: 1, tolerance: 1e-8, interval: 0.25}
outputs: [K.w, K.v, K.x]
)";
  EXPECT_EQ(ExpectTheSameSystem(LoadModelString(yaml, "when.yaml")), 0u);
  testing::Built b = testing::BuildYaml(yaml);
  testing::Trajectory tr = testing::RunDefault(b);
  // x' = w: 0 until the event at 0.5, then 2, so x(1) = 1 (rtol 1e-8 on a straight line).
  ASSERT_GE(tr.t.size(), 5u);  // the rows of the interval, and the event's two limits
  const size_t last = tr.t.size() - 1;
  EXPECT_EQ(tr.t[last], 1.0);
  EXPECT_NEAR(tr.Column("K.x", last), 1.0, 1e-6);
  EXPECT_EQ(tr.Column("K.v", last), 2.0);
}

/// A DeferredEquations whose one equation claims the form x - y = 0 but is made as written.
class OneDeferred : public DeferredEquations {
 public:
  OneDeferred(ExprPool* pool, uint32_t k, VarId x, VarId y) : pool_(pool), k_(k), x_(x), y_(y) {}
  bool Form(uint32_t k, std::vector<std::pair<VarId, double>>* terms, double* offset) const override {
    if (k != k_) return false;
    *terms = {{x_, 1.0}, {y_, -1.0}};
    *offset = 0;
    return true;
  }
  ExprId Make(uint32_t k) const override { return pool_->Sub(pool_->Var(x_), pool_->Var(y_)); }

 private:
  ExprPool* pool_;
  uint32_t k_;
  VarId x_, y_;
};

TEST(AliasEliminationTest, ADeferredEquationThatStaysIsMade) {
  // A deferred equation naming a discrete variable stays (flattening makes such equations
  // itself; this is the pass's own safety net): it is made, with the aliases substituted.
  HandSystem h;
  ExprId a = h.Var("a"), b = h.Var("b"), c = h.Var("c");
  h.var(a).discrete = true;
  h.Eq(b, c, "b = c");
  FlatEquation deferred;
  deferred.origin = EquationOrigin::kConnection;
  deferred.text = h.flat_->Own("a = b");
  h.flat_->equations.push_back(deferred);  // residual invalid
  OneDeferred later(&h.pool(), 1, VarId(h.pool().node(a).a), VarId(h.pool().node(b).a));
  AliasStats stats;
  EquationSystem sys = EliminateAliases(MakeEquationSystem(h.flat_), &stats, &later);
  ASSERT_EQ(sys.equations.size(), 1u);
  EXPECT_EQ(stats.aliases, 1u);
  // b = c made c give way to b (b comes first), so a = b stays as a - b.
  EXPECT_EQ(sys.equations[0].residual, h.pool().Sub(a, b));
}

}  // namespace
}  // namespace momenta
