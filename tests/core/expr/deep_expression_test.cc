// Long and deep expressions through the whole core: a 100 000-term sum written in a model becomes
// a balanced tree (shallow, exact), an elseif chain of 12 000 branches builds, and expressions
// 100 000 levels deep — made by substitution chains, not by the parser — go through every pass
// (substitution, evaluation, noEvent, derivatives, affine forms, printing, causalisation).

#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <unordered_map>
#include <vector>

#include "core/expr/expr_algebra.h"
#include "core/expr/expr_chain.h"
#include "core/expr/expr_eval.h"
#include "core/flatten/flat_system.h"
#include "core/lang/model_spec.h"
#include "core/lang/parser.h"
#include "tests/support/test_models.h"
#include "core/flatten/flatten.h"
#include "core/lang/yaml_loader.h"
#include "core/lang/builtin_library.h"

namespace momenta {
namespace {

/// The number of nodes on the longest path from `root` to a leaf (computed without recursion).
size_t Depth(const ExprPool& pool, ExprId root) {
  std::unordered_map<uint32_t, size_t> depth;
  std::vector<uint32_t> stack{root.value()};
  while (!stack.empty()) {
    uint32_t id = stack.back();
    const Node& n = pool.node(ExprId(id));
    const uint32_t kids[3] = {n.a, n.b, n.c};
    size_t below = 0;
    bool ready = true;
    for (int k = 0; k < Arity(n.op); ++k) {
      auto it = depth.find(kids[k]);
      if (it == depth.end()) {
        stack.push_back(kids[k]);
        ready = false;
      } else {
        below = std::max(below, it->second);
      }
    }
    if (!ready) continue;
    stack.pop_back();
    depth[id] = below + 1;
  }
  return depth.at(root.value());
}

FlatSystem FlattenYaml(const std::string& yaml) {
  return Flatten(LoadModelString(yaml, "test.yaml"), BuiltinLibrary(), {});
}

const char* kMassModel = R"(model: Long
components:
  m: {type: Mass, m: 1, s: {start: 0, fixed: true}, v: {start: 0, fixed: true}}
outputs: [)";

TEST(DeepExpressionTest, ChainsAreLeftAssociatedAsWrittenUpToARun) {
  // Up to kChainRun operands: exactly the tree the text means, ((a - b) + c) - d.
  std::vector<std::string> names = {"a", "b", "c", "d"};
  std::string tree = BuildChain(names, {false, true, false, true}, [](const std::string& x, bool inverse, const std::string& y) {
    return "(" + x + (inverse ? " - " : " + ") + y + ")";
  });
  EXPECT_EQ(tree, "(((a - b) + c) - d)");
  // Longer: halves, with the signs carried over: a - b - … regrouped keeps every term's sign.
  std::vector<double> values;
  std::vector<bool> inverse;
  for (int k = 1; k <= 1000; ++k) {
    values.push_back(k);
    inverse.push_back(k > 1 && k % 2 == 0);
  }
  double sum = BuildChain(values, inverse, [](double x, bool inv, double y) { return inv ? x - y : x + y; });
  double expected = 0;
  for (int k = 1; k <= 1000; ++k) expected += (k > 1 && k % 2 == 0) ? -k : k;
  EXPECT_EQ(sum, expected);
  // Products and quotients regroup the same way: 2 / 2 * 2 / 2 … = 1 or 2.
  std::vector<double> twos(999, 2.0);
  std::vector<bool> divide(999);
  for (size_t k = 1; k < divide.size(); ++k) divide[k] = k % 2 == 1;
  EXPECT_EQ(BuildChain(twos, divide, [](double x, bool inv, double y) { return inv ? x / y : x * y; }), 2.0);
}

TEST(DeepExpressionTest, SumOfOneToOneHundredThousandIsExact) {
  std::string sum = "1", difference = "m.s", product = "1";
  for (int k = 2; k <= 100000; ++k) sum += " + " + std::to_string(k);
  for (int k = 1; k <= 100000; ++k) difference += " - " + std::to_string(k) + " + 0";
  for (int k = 1; k <= 1000; ++k) product += k % 2 ? " * 2" : " / 2";
  FlatSystem flat = FlattenYaml(std::string(kMassModel) + "\"" + sum + "\", \"" + difference + "\", \"" + product + "\"]\n");
  const ExprPool& pool = *flat.pool;
  ASSERT_EQ(flat.outputs.size(), 3u);
  // Constant folding of the balanced tree: exact in doubles.
  EXPECT_EQ(Evaluate(pool, flat.outputs[0].expr, {}), 5000050000.0);
  // m.s - 1 + 0 - 2 + 0 …, with m.s = 0: a tree of depth about log2(200 000).
  EXPECT_EQ(Evaluate(pool, flat.outputs[1].expr, {}), -5000050000.0);
  EXPECT_LE(Depth(pool, flat.outputs[1].expr), kChainRun + 20);
  EXPECT_EQ(Evaluate(pool, flat.outputs[2].expr, {}), 1.0);
}

TEST(DeepExpressionTest, LongSumInAComponentEquationSimulates) {
  // der(x) = -x + 0.5*x - 0.5*x + … : the terms cancel in pairs, x(t) = exp(-t).
  std::string rhs = "-x";
  for (int k = 0; k < 20000; ++k) rhs += " + 0.5*x - 0.5*x";
  testing::Built b = testing::BuildYaml(R"(model: LongEquation
define:
  Decay:
    variables: {x: {start: 1, fixed: true}}
    equations: ["der(x) = )" + rhs + R"("]
components:
  d: {type: Decay}
experiment: {stop: 1, tolerance: 1e-8}
outputs: [d.x]
)");
  testing::Trajectory tr = testing::RunDefault(b);
  ASSERT_FALSE(tr.t.empty());
  EXPECT_EQ(tr.t.back(), 1.0);
  EXPECT_NEAR(tr.Column("d.x", tr.t.size() - 1), std::exp(-1.0), 1e-6);
}

std::string Repeat(const std::string& s, int n) {
  std::string out;
  for (int k = 0; k < n; ++k) out += s;
  return out;
}

TEST(DeepExpressionTest, NestingAtTheLimitGoesThroughEveryPass) {
  // der(x) = -(-(…-(x)…)) with 255 signs, each in parentheses: -x; x(0) = k = ((…(1)…)); the
  // output nests 255 abs().
  const int n = kMaxExpressionDepth - 1;
  testing::Built b = testing::BuildYaml(R"(model: Nested
define:
  Decay:
    parameters: {k: {value: ")" + Repeat("(", n) + "1" + Repeat(")", n) + R"("}}
    variables: {x: {start: k, fixed: true}}
    equations: ["der(x) = )" + Repeat("-(", n) + "x" + Repeat(")", n) + R"("]
components:
  d: {type: Decay}
experiment: {stop: 1, tolerance: 1e-8}
outputs: [")" + Repeat("abs(", n) + "d.x" + Repeat(")", n) + R"("]
)");
  testing::Trajectory tr = testing::RunDefault(b);
  ASSERT_FALSE(tr.t.empty());
  EXPECT_NEAR(tr.values.back().at(0), std::exp(-1.0), 1e-6);
}

TEST(DeepExpressionTest, ElseifChainBuildsAndPicksTheFirstTrueBranch) {
  // if time > 1 then -1 elseif m.s < 1 and 1 > k then k … : the first true branch is k = 2.
  std::string text = "if time > 1 then -1";
  for (int k = 1; k <= 12000; ++k) text += " elseif m.s < 1 and " + std::to_string(k) + " > 1 then " + std::to_string(k);
  text += " else 0";
  FlatSystem flat = FlattenYaml(std::string(kMassModel) + "\"" + text + "\"]\n");
  std::vector<double> vars(flat.variables.size(), 0.0);
  LeafValues lv;
  lv.vars = vars.data();
  EXPECT_EQ(Evaluate(*flat.pool, flat.outputs[0].expr, lv), 2.0);
  lv.time = 2;
  EXPECT_EQ(Evaluate(*flat.pool, flat.outputs[0].expr, lv), -1.0);
  // noEvent() over the whole chain flags its relations without recursion.
  ExprId quiet = flat.pool->NoEvent(flat.outputs[0].expr);
  EXPECT_NE(quiet, flat.outputs[0].expr);
  EXPECT_EQ(Evaluate(*flat.pool, quiet, lv), -1.0);
}

TEST(DeepExpressionTest, SubstitutionChainOf100000WalksEveryPass) {
  // x_k = x_{k-1} + 1 for k = 1..n, x_0 = y: x_n = y + n, an expression n levels deep.
  constexpr uint32_t n = 100000;
  ExprPool pool;
  Substitution s(&pool);
  for (uint32_t k = 1; k <= n; ++k) s.Set(pool.Var(VarId(k)), pool.Add(pool.Var(VarId(k - 1)), pool.One()));
  ExprId deep = s.Apply(pool.Var(VarId(n)));
  ASSERT_GE(Depth(pool, deep), size_t{n});
  ExprId y = pool.Var(VarId(0u));
  std::vector<double> vars(n + 1, 0.0);
  vars[0] = 0.5;
  LeafValues lv;
  lv.vars = vars.data();
  EXPECT_EQ(Evaluate(pool, deep, lv), 0.5 + n);
  // Derivatives: d/dy = 1, d/dt = der(y).
  EXPECT_EQ(PartialDerivative(&pool, deep, y), pool.One());
  EXPECT_EQ(TimeDerivative(&pool, deep), pool.Der(VarId(0u)));
  // Affine form: y + n.
  AffineForm form;
  ASSERT_TRUE(DecomposeAffine(&pool, deep, 4, &form));
  ASSERT_EQ(form.terms.size(), 1u);
  EXPECT_EQ(form.terms[0].first, y);
  EXPECT_EQ(Evaluate(pool, form.offset, lv), double{n});
  // A relation on it, quietened, and printed (elided).
  ExprId rel = pool.NoEvent(pool.Binary(Op::kGt, deep, pool.Const(3)));
  EXPECT_TRUE(pool.node(rel).flags & kNoEvent);
  std::string text = ToString(pool, rel, ExprNamer{});
  EXPECT_LT(text.size(), 5000u);
  EXPECT_NE(text.find("…"), std::string::npos);
}

TEST(DeepExpressionTest, CausalisedChainOf20000EquationsBuilds) {
  // A[i].y = G[i].y + 1, G[i].y = k*G[i].u, G[i+1].u = A[i].y: each unknown is solved from the
  // previous one, so the output is an expression 2n levels deep; with k = 1 it is sin(2 pi t) + n.
  testing::Built b = testing::BuildYaml(R"(model: GainChain
parameters: {n: 20000}
define:
  AddOne:
    connectors: {u: {type: RealInput}, y: {type: RealOutput}}
    equations: [y = u + 1]
components:
  src: {type: Sine, amplitude: 1, f: 1}
  G: {type: Gain, count: n, k: 1}
  A: {type: AddOne, count: n}
connections:
  - [src.y, "G[1].u"]
  - {for: "i in 1:n-1", connect: ["G[i].y", "A[i].u"]}
  - {for: "i in 1:n-1", connect: ["A[i].y", "G[i+1].u"]}
  - ["G[n].y", "A[n].u"]
experiment: {stop: 0.25, interval: 0.25}
outputs: ["A[n].y"]
)");
  EXPECT_EQ(b.model->unknowns.size(), 0u);  // every equation solved explicitly
  testing::Trajectory tr = testing::RunDefault(b);
  ASSERT_FALSE(tr.t.empty());
  EXPECT_EQ(tr.Column("A[n].y", 0), 20000.0);
  EXPECT_NEAR(tr.Column("A[n].y", tr.t.size() - 1), 20001.0, 1e-9);
}

}  // namespace
}  // namespace momenta
