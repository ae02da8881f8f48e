// Symbolic algebra on the pool: partial and time derivatives of every function against central
// finite differences of Evaluate(), substitution chains, affine decomposition (including a
// 100 000-term sum), SolveFor, ReplaceLeaf, CollectLeaves and the printer's precedence (round trip
// through the parser).

#include "core/expr/expr_algebra.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <cmath>
#include <functional>
#include <map>
#include <random>
#include <string>
#include <vector>

#include "core/expr/expr_eval.h"
#include "core/lang/parser.h"

namespace momenta {
namespace {

constexpr int kNumVars = 3;

class ExprAlgebraTest : public ::testing::Test {
 protected:
  ExprPool pool;
  ExprId x = pool.Var(VarId(0u));
  ExprId y = pool.Var(VarId(1u));
  ExprId z = pool.Var(VarId(2u));
  ExprId p = pool.Param(ParamId(0u));
  ExprId q = pool.Param(ParamId(1u));

  ExprId F(Op op, ExprId a) { return pool.Unary(op, a); }
  ExprId F(Op op, ExprId a, ExprId b) { return pool.Binary(op, a, b); }
  ExprId C(double v) { return pool.Const(v); }

  double Eval(ExprId e, const std::vector<double>& vars, const std::vector<double>& params = {1.5, -0.5},
              double time = 0, const std::vector<double>& ders = {}) {
    LeafValues lv;
    lv.vars = vars.data();
    lv.params = params.data();
    lv.ders = ders.empty() ? nullptr : ders.data();
    lv.time = time;
    return Evaluate(pool, e, lv);
  }

  /// d e / d var_k by central differences.
  double FiniteDifference(ExprId e, std::vector<double> at, int k) {
    const double h = 1e-6 * std::max(1.0, std::fabs(at[k]));
    std::vector<double> plus = at, minus = at;
    plus[k] += h;
    minus[k] -= h;
    return (Eval(e, plus) - Eval(e, minus)) / (2 * h);
  }

  void ExpectPartialsMatch(ExprId e, const std::vector<double>& at, const std::string& what) {
    for (int k = 0; k < kNumVars; ++k) {
      ExprId d = PartialDerivative(&pool, e, pool.Var(VarId(static_cast<uint32_t>(k))));
      double fd = FiniteDifference(e, at, k);
      EXPECT_NEAR(Eval(d, at), fd, 1e-6 * std::max(1.0, std::fabs(fd)))
          << what << ": d/dx" << k << " at (" << at[0] << ", " << at[1] << ", " << at[2] << ")";
    }
  }
};

TEST_F(ExprAlgebraTest, PartialDerivativesOfEveryFunctionMatchFiniteDifferences) {
  // Arguments inside each function's domain: u in (-1, 1) for asin/acos, positive for log/sqrt.
  ExprId u = pool.Mul(C(0.3), pool.Add(x, pool.Mul(y, z)));  // small
  ExprId pos = pool.Add(C(2), pool.Mul(x, x));               // > 0
  std::vector<std::pair<std::string, ExprId>> cases = {
      {"x+y", pool.Add(x, y)},
      {"x-y*z", pool.Sub(x, pool.Mul(y, z))},
      {"-x*y", pool.Neg(pool.Mul(x, y))},
      {"x/y", pool.Div(x, y)},
      {"sin", F(Op::kSin, pool.Mul(x, y))},
      {"cos", F(Op::kCos, pool.Mul(x, y))},
      {"tan", F(Op::kTan, u)},
      {"asin", F(Op::kAsin, u)},
      {"acos", F(Op::kAcos, u)},
      {"atan", F(Op::kAtan, pool.Mul(x, z))},
      {"sinh", F(Op::kSinh, pool.Add(x, y))},
      {"cosh", F(Op::kCosh, pool.Sub(x, z))},
      {"tanh", F(Op::kTanh, pool.Mul(x, y))},
      {"exp", F(Op::kExp, pool.Mul(x, z))},
      {"log", F(Op::kLog, pool.Mul(pos, y))},
      {"log10", F(Op::kLog10, pool.Mul(pos, y))},
      {"sqrt", F(Op::kSqrt, pool.Mul(pos, y))},
      {"abs", F(Op::kAbs, pool.Sub(x, y))},
      {"sign", pool.Mul(F(Op::kSign, pool.Sub(x, y)), z)},
      {"atan2", F(Op::kAtan2, pool.Add(x, z), y)},
      {"min", F(Op::kMin, pool.Mul(x, z), y)},
      {"max", F(Op::kMax, pool.Mul(x, z), y)},
      {"x^2", pool.Pow(x, C(2))},
      {"x^3", pool.Pow(pool.Add(x, z), C(3))},
      {"x^-1.5", pool.Pow(pos, C(-1.5))},
      {"x^0.5", pool.Pow(pos, C(0.5))},
      {"y^x (variable exponent)", pool.Pow(y, pool.Mul(x, z))},
      {"2^x", pool.Pow(C(2), pool.Mul(x, y))},
      {"p^x (parameter base)", pool.Pow(pool.Add(p, C(1)), x)},
      {"if", pool.If(pool.Binary(Op::kGt, x, y), pool.Mul(x, x), F(Op::kSin, pool.Mul(y, z)))},
      {"nested", pool.Add(F(Op::kSin, pool.Mul(x, y)), F(Op::kExp, pool.Div(z, pos)))},
  };
  // Points where every case is smooth (y > 0 for logs of pos*y; away from kinks of abs/min/max).
  const std::vector<std::vector<double>> points = {{0.7, 1.3, -0.4}, {-1.1, 0.6, 0.9}, {2.0, 0.45, 0.3}};
  for (const auto& [name, e] : cases) {
    for (const auto& at : points) ExpectPartialsMatch(e, at, name);
  }
}

TEST_F(ExprAlgebraTest, PartialDerivativesOfARowAreThoseOfPartialDerivative) {
  // A Jacobian row leaf by leaf from one walk: the same nodes as PartialDerivative gives (ids are
  // structure in the pool), including shared subexpressions, der() leaves, a leaf only in an
  // if-condition (0) and a leaf that does not occur (0).
  ExprId dx = pool.Der(VarId(0u));
  ExprId shared = pool.Div(pool.Sub(x, p), pool.Add(y, q));
  std::vector<std::pair<std::string, ExprId>> cases = {
      {"shared", pool.Sub(pool.Mul(shared, shared), pool.Mul(dx, F(Op::kSin, shared)))},
      {"a/b with b' = 0", pool.Sub(pool.Neg(pool.Div(pool.Sub(x, y), p)), dx)},
      {"if", pool.If(pool.Binary(Op::kGt, z, y), pool.Mul(x, dx), F(Op::kCos, pool.Mul(y, x)))},
      {"atan2", F(Op::kAtan2, pool.Add(x, z), pool.Mul(y, dx))},
      {"pow", pool.Pow(pool.Add(y, C(2)), pool.Mul(x, z))},
      {"leaf", x},
  };
  // An if-condition with a leaf that comes again later in the walk: the leaves' order is
  // CollectLeaves' all the same.
  cases.push_back({"condition leaf again", pool.Add(pool.If(pool.Binary(Op::kGt, z, y), x, dx), pool.Mul(z, x))});
  PartialDerivatives partials(&pool);
  for (const auto& [name, e] : cases) {
    partials.Reset(e, kHasVar | kHasDer);
    EXPECT_EQ(partials.Leaves(), CollectLeaves(pool, e, kHasVar | kHasDer)) << name;
    for (ExprId leaf : {x, y, z, dx}) {
      const ExprId ours = partials.Of(leaf);
      EXPECT_EQ(ours, PartialDerivative(&pool, e, leaf)) << name;
    }
  }
  // z occurs only in the if's condition: its partial is 0.
  partials.Reset(cases[2].second, kHasVar | kHasDer);
  EXPECT_EQ(partials.Of(z), pool.Zero());
}

TEST_F(ExprAlgebraTest, PartialDerivativesOfADivisionByAParameterMakeOnlyTheirValue) {
  // d/dx (x - y)/p = 1/p: one node, and no p*p (the general quotient rule's, which nothing reads).
  const ExprId e = pool.Div(pool.Sub(x, y), p);
  PartialDerivatives partials(&pool);
  partials.Reset(e, kHasVar);
  const size_t before = pool.size();
  const ExprId d = partials.Of(x);
  EXPECT_EQ(pool.size(), before + 1);
  EXPECT_EQ(d, pool.Div(pool.One(), p));
  EXPECT_EQ(partials.Of(y), PartialDerivative(&pool, e, y));
}

TEST_F(ExprAlgebraTest, PartialDerivativeByParameterAndByDerivative) {
  ExprId dx = pool.Der(VarId(0u));
  ExprId e = pool.Add(pool.Mul(p, pool.Mul(dx, y)), pool.Mul(q, x));
  EXPECT_EQ(PartialDerivative(&pool, e, dx), pool.Mul(p, y));
  EXPECT_EQ(PartialDerivative(&pool, e, x), q);
  EXPECT_EQ(PartialDerivative(&pool, e, p), pool.Mul(dx, y));
  // Leaves that do not occur: zero, without walking.
  EXPECT_EQ(PartialDerivative(&pool, e, z), pool.Zero());
  EXPECT_EQ(PartialDerivative(&pool, pool.Time(), x), pool.Zero());
  // der(x) and x are different leaves.
  EXPECT_EQ(PartialDerivative(&pool, pool.Mul(x, x), dx), pool.Zero());
  // A relation is piecewise constant.
  EXPECT_EQ(PartialDerivative(&pool, pool.Binary(Op::kLt, x, y), x), pool.Zero());
}

TEST_F(ExprAlgebraTest, TimeDerivativeFollowsTheChainRule) {
  // Along x_k(t) = x_k0 + v_k*t, d/dt e(x(t), t) against central differences in t.
  std::vector<double> x0 = {0.4, 1.2, -0.3}, v = {0.5, 0.8, 2.0};
  ExprId t = pool.Time();
  std::vector<std::pair<std::string, ExprId>> cases = {
      {"sin(x*y)+t", pool.Add(F(Op::kSin, pool.Mul(x, y)), t)},
      {"p*x^2*t", pool.Mul(pool.Mul(p, pool.Pow(x, C(2))), t)},
      {"atan2(y, x+z)", F(Op::kAtan2, y, pool.Add(x, z))},
      {"y^x", pool.Pow(y, x)},
      {"exp(-t)*cos(z)", pool.Mul(F(Op::kExp, pool.Neg(t)), F(Op::kCos, z))},
      {"sqrt(1+x^2)/y", pool.Div(F(Op::kSqrt, pool.Add(C(1), pool.Mul(x, x))), y)},
      {"if", pool.If(pool.Binary(Op::kLt, t, C(0.5)), pool.Mul(x, t), pool.Mul(y, z))},
      {"max", F(Op::kMax, pool.Mul(x, t), pool.Sub(y, t))},
      {"log10(y*y)", F(Op::kLog10, pool.Mul(y, y))},
  };
  for (const auto& [name, e] : cases) {
    ExprId d = TimeDerivative(&pool, e);
    ASSERT_TRUE(d.valid()) << name;
    for (double t0 : {0.1, 0.3, 0.9}) {
      auto at = [&](double tt) {
        std::vector<double> xs(3);
        for (int k = 0; k < 3; ++k) xs[k] = x0[k] + v[k] * tt;
        return Eval(e, xs, {1.5, -0.5}, tt);
      };
      std::vector<double> xs(3);
      for (int k = 0; k < 3; ++k) xs[k] = x0[k] + v[k] * t0;
      const double h = 1e-6;
      double fd = (at(t0 + h) - at(t0 - h)) / (2 * h);
      EXPECT_NEAR(Eval(d, xs, {1.5, -0.5}, t0, v), fd, 1e-6 * std::max(1.0, std::fabs(fd)))
          << name << " at t = " << t0;
    }
  }
}

TEST_F(ExprAlgebraTest, TimeDerivativeLeaves) {
  EXPECT_EQ(TimeDerivative(&pool, x), pool.Der(VarId(0u)));
  EXPECT_EQ(TimeDerivative(&pool, pool.Time()), pool.One());
  EXPECT_EQ(TimeDerivative(&pool, pool.Mul(p, q)), pool.Zero());
  EXPECT_EQ(TimeDerivative(&pool, pool.Pre(VarId(0u))), pool.Zero());
  EXPECT_EQ(TimeDerivative(&pool, pool.Sub(pool.Mul(C(2), x), y)),
            pool.Sub(pool.Mul(C(2), pool.Der(VarId(0u))), pool.Der(VarId(1u))));
  // Derivatives of derivatives: der(der(x)), and the product rule through them.
  EXPECT_EQ(TimeDerivative(&pool, pool.Der(VarId(0u))), pool.Der(VarId(0u), 2));
  EXPECT_EQ(pool.DerOrder(pool.Der(VarId(0u), 3)), 3u);
  EXPECT_EQ(TimeDerivative(&pool, pool.Mul(y, pool.Der(VarId(2u)))),
            pool.Add(pool.Mul(pool.Der(VarId(1u)), pool.Der(VarId(2u))), pool.Mul(y, pool.Der(VarId(2u), 2))));
}

TEST_F(ExprAlgebraTest, SubstitutionResolvesChains) {
  Substitution s(&pool);
  // x -> y + 1, y -> 2*z: x becomes 2*z + 1, whatever order the entries come in.
  s.Set(x, pool.Add(y, C(1)));
  s.Set(y, pool.Mul(C(2), z));
  EXPECT_TRUE(s.Has(x));
  EXPECT_TRUE(s.Has(y));
  EXPECT_FALSE(s.Has(z));
  EXPECT_EQ(s.size(), 2u);
  EXPECT_EQ(s.Apply(x), pool.Add(pool.Mul(C(2), z), C(1)));
  EXPECT_EQ(s.Apply(pool.Mul(x, y)), pool.Mul(pool.Add(pool.Mul(C(2), z), C(1)), pool.Mul(C(2), z)));
  // Untouched expressions keep their id.
  ExprId other = pool.Add(z, F(Op::kSin, p));
  EXPECT_EQ(s.Apply(other), other);
  // A later entry invalidates memoised results.
  s.Set(z, C(3));
  EXPECT_TRUE(pool.IsConst(s.Apply(x), 7.0));
  // Replacing an entry does not count twice.
  s.Set(z, C(4));
  EXPECT_EQ(s.size(), 3u);
  EXPECT_TRUE(pool.IsConst(s.Apply(x), 9.0));
  // der() and pre() leaves are separate entries.
  EXPECT_EQ(s.Apply(pool.Der(VarId(0u))), pool.Der(VarId(0u)));
}

TEST_F(ExprAlgebraTest, SubstitutionKeepsEachKindOfLeafApart) {
  // x, der(x), der(der(x)), pre(x) and the parameter with x's number are different leaves: each
  // maps to its own replacement, and a constant leaf can be mapped too.
  ExprId dx = pool.Der(VarId(0u)), ddx = pool.Der(VarId(0u), 2), px = pool.Pre(VarId(0u));
  ExprId p0 = pool.Param(ParamId(0u));
  Substitution s(&pool);
  s.Set(ddx, pool.Mul(C(5), y));
  EXPECT_TRUE(s.Has(ddx));
  EXPECT_FALSE(s.Has(dx));
  EXPECT_FALSE(s.Has(x));
  s.Set(x, pool.Add(y, C(1)));
  s.Set(dx, pool.Mul(C(2), y));
  s.Set(px, z);
  s.Set(p0, q);
  EXPECT_EQ(s.size(), 5u);
  for (ExprId leaf : {x, dx, ddx, px, p0}) EXPECT_TRUE(s.Has(leaf));
  EXPECT_FALSE(s.Has(pool.Der(VarId(1u))));
  EXPECT_FALSE(s.Has(pool.Pre(VarId(1u))));
  EXPECT_FALSE(s.Has(pool.Param(ParamId(1u))));
  // A variable far beyond any mapped so far.
  EXPECT_FALSE(s.Has(pool.Var(VarId(100000u))));
  ExprId e = pool.Add(pool.Add(x, dx), pool.Add(ddx, pool.Add(px, p0)));
  ExprId expected = pool.Add(pool.Add(pool.Add(y, C(1)), pool.Mul(C(2), y)),
                             pool.Add(pool.Mul(C(5), y), pool.Add(z, q)));
  EXPECT_EQ(s.Apply(e), expected);
  // The memo given back, the same rewrite again.
  s.ReleaseMemo();
  EXPECT_EQ(s.Apply(e), expected);
  EXPECT_EQ(s.Apply(pool.Mul(e, x)), pool.Mul(expected, pool.Add(y, C(1))));
  // A mapped constant: any subtree may hold it.
  s.Set(C(7), C(8));
  EXPECT_TRUE(s.Touches(pool.Add(y, C(7))));
  EXPECT_TRUE(pool.IsConst(s.Apply(C(7)), 8.0));
}

TEST_F(ExprAlgebraTest, SubstitutionOf100000LongChain) {
  // x_k -> x_{k+1} + 1 for k < N: x_0 becomes x_N + N through a 100 000-deep chain.
  const uint32_t n = 100000;
  Substitution s(&pool);
  for (uint32_t k = 0; k < n; ++k) s.Set(pool.Var(VarId(k)), pool.Add(pool.Var(VarId(k + 1)), C(1)));
  ExprId r = s.Apply(pool.Var(VarId(0u)));
  AffineForm form;
  ASSERT_TRUE(DecomposeAffine(&pool, r, 4, &form));
  ASSERT_EQ(form.terms.size(), 1u);
  EXPECT_EQ(form.terms[0].first, pool.Var(VarId(n)));
  EXPECT_EQ(form.terms[0].second, 1.0);
  EXPECT_TRUE(pool.IsConst(form.offset, static_cast<double>(n)));
}

TEST_F(ExprAlgebraTest, SubstitutionLeavesExpressionsWithoutAMappedLeafAsTheyAre) {
  // Only der(x) is mapped: expressions without it keep their id, are reported untouched, and
  // cost no new node (passes skip them; the result must be what Apply gives).
  ExprId dx = pool.Der(VarId(0u));
  Substitution s(&pool);
  EXPECT_FALSE(s.Touches(x));
  s.Set(dx, pool.Mul(C(2), y));
  ExprId without = pool.Add(pool.Mul(x, F(Op::kSin, y)), pool.Div(p, q));
  ExprId with = pool.Sub(dx, pool.Mul(x, z));
  const size_t nodes = pool.size();
  EXPECT_FALSE(s.Touches(without));
  EXPECT_EQ(s.Apply(without), without);
  EXPECT_EQ(pool.size(), nodes);
  EXPECT_TRUE(s.Touches(with));
  EXPECT_TRUE(s.Touches(pool.Mul(with, without)));
  EXPECT_EQ(s.Apply(with), pool.Sub(pool.Mul(C(2), y), pool.Mul(x, z)));
  // A variable mapped later: the skipped kinds follow.
  s.Set(z, C(3));
  EXPECT_TRUE(s.Touches(pool.Add(z, p)));
  EXPECT_EQ(s.Apply(with), pool.Sub(pool.Mul(C(2), y), pool.Mul(x, C(3))));
  EXPECT_FALSE(s.Touches(pool.Add(y, pool.Pre(VarId(2u)))));
}

TEST_F(ExprAlgebraTest, ReplaceLeaf) {
  ExprId e = pool.Add(pool.Mul(x, y), pool.Unary(Op::kSin, x));
  ExprId r = ReplaceLeaf(&pool, e, x, C(2));
  EXPECT_EQ(r, pool.Add(pool.Mul(C(2), y), C(std::sin(2.0))));
  // A leaf that does not occur: the same node.
  EXPECT_EQ(ReplaceLeaf(&pool, e, z, C(5)), e);
  // By an expression; and the replaced variable is gone.
  ExprId r2 = ReplaceLeaf(&pool, e, x, pool.Add(z, p));
  EXPECT_FALSE(ContainsLeaf(pool, r2, x));
  EXPECT_TRUE(ContainsLeaf(pool, r2, z));
  EXPECT_DOUBLE_EQ(Eval(r2, {0, 3, 0.25}), (0.25 + 1.5) * 3 + std::sin(0.25 + 1.5));
  // Parameters and der() leaves can be replaced too.
  EXPECT_EQ(ReplaceLeaf(&pool, pool.Mul(p, x), p, C(1)), x);
  ExprId dx = pool.Der(VarId(0u));
  EXPECT_EQ(ReplaceLeaf(&pool, pool.Sub(dx, y), dx, x), pool.Sub(x, y));
}

TEST_F(ExprAlgebraTest, CollectLeaves) {
  ExprId dx = pool.Der(VarId(0u)), pre = pool.Pre(VarId(1u));
  ExprId e = pool.Add(pool.Mul(x, pool.Mul(p, dx)), pool.Add(pool.Mul(x, pre), pool.Sub(y, p)));
  auto sorted = [](std::vector<ExprId> v) {
    std::sort(v.begin(), v.end());
    return v;
  };
  EXPECT_EQ(sorted(CollectLeaves(pool, e, kHasVar)), sorted({x, y}));
  EXPECT_EQ(sorted(CollectLeaves(pool, e, kHasParam)), std::vector<ExprId>{p});
  EXPECT_EQ(sorted(CollectLeaves(pool, e, kHasDer)), std::vector<ExprId>{dx});
  EXPECT_EQ(sorted(CollectLeaves(pool, e, kHasPre)), std::vector<ExprId>{pre});
  EXPECT_EQ(sorted(CollectLeaves(pool, e, kHasVar | kHasDer | kHasPre | kHasParam)),
            sorted({x, y, dx, pre, p}));
  EXPECT_TRUE(CollectLeaves(pool, pool.Time(), kHasVar).empty());
  // Many distinct leaves (past the small linear scan) and a shared DAG: each once.
  ExprId sum = pool.Zero();
  std::vector<ExprId> want;
  for (uint32_t k = 0; k < 500; ++k) {
    ExprId v = pool.Var(VarId(k));
    want.push_back(v);
    sum = pool.Add(sum, pool.Mul(v, v));
  }
  ExprId shared = pool.Mul(sum, pool.Add(sum, F(Op::kSin, sum)));
  EXPECT_EQ(sorted(CollectLeaves(pool, shared, kHasVar)), sorted(want));
  EXPECT_TRUE(ContainsLeaf(pool, shared, pool.Var(VarId(499u))));
  EXPECT_FALSE(ContainsLeaf(pool, shared, pool.Var(VarId(500u))));
  EXPECT_FALSE(ContainsLeaf(pool, shared, pool.Der(VarId(3u))));
}

TEST_F(ExprAlgebraTest, DecomposeAffine) {
  AffineForm form;
  // 3x - 2y + p + 5
  ExprId e = pool.Add(pool.Sub(pool.Mul(C(3), x), pool.Mul(y, C(2))), pool.Add(p, C(5)));
  ASSERT_TRUE(DecomposeAffine(&pool, e, 10, &form));
  std::map<uint32_t, double> coef;
  for (auto& [leaf, c] : form.terms) coef[leaf.value()] = c;
  EXPECT_EQ(coef.size(), 2u);
  EXPECT_EQ(coef[x.value()], 3.0);
  EXPECT_EQ(coef[y.value()], -2.0);
  EXPECT_TRUE(pool.IsParamOnly(form.offset));
  EXPECT_DOUBLE_EQ(Eval(form.offset, {}), 1.5 + 5);
  // Negation, division by a number, der() leaves; terms that cancel are dropped.
  ExprId dx = pool.Der(VarId(0u));
  e = pool.Sub(pool.Neg(pool.Div(pool.Sub(dx, y), C(4))), pool.Neg(pool.Div(y, C(-4))));
  ASSERT_TRUE(DecomposeAffine(&pool, e, 10, &form));
  ASSERT_EQ(form.terms.size(), 1u);
  EXPECT_EQ(form.terms[0].first, dx);
  EXPECT_EQ(form.terms[0].second, -0.25);
  EXPECT_EQ(form.offset, pool.Zero());
  ASSERT_TRUE(DecomposeAffine(&pool, pool.Add(pool.Sub(x, y), pool.Sub(y, x)), 10, &form));
  EXPECT_TRUE(form.terms.empty());
  // A parameter-only expression is all offset.
  ASSERT_TRUE(DecomposeAffine(&pool, pool.Mul(p, q), 10, &form));
  EXPECT_TRUE(form.terms.empty());
  EXPECT_EQ(form.offset, pool.Mul(p, q));
  // Not affine with numeric coefficients.
  EXPECT_FALSE(DecomposeAffine(&pool, pool.Mul(x, y), 10, &form));
  EXPECT_FALSE(DecomposeAffine(&pool, pool.Mul(p, x), 10, &form));
  EXPECT_FALSE(DecomposeAffine(&pool, pool.Div(x, y), 10, &form));
  EXPECT_FALSE(DecomposeAffine(&pool, F(Op::kSin, x), 10, &form));
  EXPECT_FALSE(DecomposeAffine(&pool, pool.Add(x, pool.Time()), 10, &form));
  // Too many terms.
  EXPECT_FALSE(DecomposeAffine(&pool, pool.Add(pool.Add(x, y), z), 2, &form));
  EXPECT_TRUE(DecomposeAffine(&pool, pool.Add(pool.Add(x, y), z), 3, &form));
}

TEST_F(ExprAlgebraTest, DecomposeAffineOf100000TermSum) {
  // A flow sum over a 100 000-member connection set: a 100 000-deep chain of additions.
  const uint32_t n = 100000;
  ExprId distinct = pool.Var(VarId(0u));
  for (uint32_t k = 1; k < n; ++k) distinct = pool.Add(distinct, pool.Var(VarId(k)));
  // The same few variables over and over, with parameter offsets in between.
  ExprId repeated = pool.Zero();
  for (uint32_t k = 0; k < n; ++k) {
    repeated = pool.Add(repeated, pool.Var(VarId(k % 2)));
    if (k % 1000 == 0) repeated = pool.Add(repeated, p);
  }
  AffineForm form;
  // Alias elimination asks for at most 2 terms: a quick "no".
  EXPECT_FALSE(DecomposeAffine(&pool, distinct, 2, &form));
  ASSERT_TRUE(DecomposeAffine(&pool, repeated, 2, &form));
  ASSERT_EQ(form.terms.size(), 2u);
  EXPECT_EQ(form.terms[0].second, n / 2);
  EXPECT_EQ(form.terms[1].second, n / 2);
  EXPECT_DOUBLE_EQ(Eval(form.offset, {}), 100 * 1.5);
}

TEST_F(ExprAlgebraTest, DecomposeAffineHandlesAManyTermSum) {
  // A flow sum over a large connection set: 30 000 distinct leaves, each with coefficient 1, plus
  // one leaf repeated (coefficient 2) and one cancelled (x - x). Speed is the benchmarks' business
  // (no timing here); a quadratic merge of the terms would make this test take seconds.
  const uint32_t n = 30000;
  ExprId sum = pool.Var(VarId(0u));
  for (uint32_t k = 1; k < n; ++k) sum = pool.Add(sum, pool.Var(VarId(k)));
  sum = pool.Add(sum, pool.Var(VarId(7u)));
  sum = pool.Sub(pool.Add(sum, pool.Var(VarId(n + 1))), pool.Var(VarId(n + 1)));
  AffineForm form;
  ASSERT_TRUE(DecomposeAffine(&pool, sum, n + 2, &form));
  ASSERT_EQ(form.terms.size(), n);
  for (const auto& t : form.terms) {
    ASSERT_EQ(t.second, pool.node(t.first).a == 7u ? 2.0 : 1.0) << "leaf " << pool.node(t.first).a;
  }
  // With a cap below the number of terms it refuses.
  EXPECT_FALSE(DecomposeAffine(&pool, sum, n - 1, &form));
}

TEST_F(ExprAlgebraTest, SolveForLinear) {
  ExprId coefficient;
  // 2x + 3y - 4 = 0  =>  x = (4 - 3y)/2
  ExprId r = pool.Sub(pool.Add(pool.Mul(C(2), x), pool.Mul(C(3), y)), C(4));
  ExprId sol = SolveFor(&pool, r, x, false, &coefficient);
  ASSERT_TRUE(sol.valid());
  EXPECT_TRUE(pool.IsConst(coefficient, 2.0));
  EXPECT_FALSE(ContainsLeaf(pool, sol, x));
  for (double yv : {-1.0, 0.0, 2.5}) EXPECT_DOUBLE_EQ(Eval(sol, {0, yv, 0}), (4 - 3 * yv) / 2);
  // Unit coefficients give no division.
  EXPECT_EQ(SolveFor(&pool, pool.Sub(x, pool.Mul(y, z)), x, false, nullptr), pool.Mul(y, z));
  EXPECT_EQ(SolveFor(&pool, pool.Sub(pool.Mul(y, z), x), x, false, nullptr), pool.Mul(y, z));
  // x inside a nonlinear function of other variables is fine as long as x enters linearly.
  sol = SolveFor(&pool, pool.Sub(pool.Mul(C(-4), x), F(Op::kSin, pool.Mul(y, z))), x, false, nullptr);
  ASSERT_TRUE(sol.valid());
  EXPECT_DOUBLE_EQ(Eval(sol, {0, 0.5, 2}), -std::sin(1.0) / 4);
  // Solving for der(x).
  ExprId dx = pool.Der(VarId(0u));
  EXPECT_EQ(SolveFor(&pool, pool.Sub(y, dx), dx, false, nullptr), y);
}

TEST_F(ExprAlgebraTest, SolvingAnExplicitEquationBuildsWhatTheGeneralStepsWould) {
  // x - rest and rest - x, rest free of x, are solved without differentiating: the solution and
  // the coefficient are those of the general steps, and the pool grows by what they would add
  // (0 - rest for x - rest, nothing for rest - x), so node numbers downstream stay the same.
  ExprId coefficient;
  const ExprId rest = pool.Add(pool.Mul(p, y), pool.Mul(C(2), z));
  size_t before = pool.size();
  const ExprId minus_rest = pool.Sub(C(0), rest);
  const size_t with_negation = pool.size() - before;
  before = pool.size();
  EXPECT_EQ(SolveFor(&pool, pool.Sub(x, rest), x, false, &coefficient), rest);
  EXPECT_EQ(coefficient, pool.One());
  EXPECT_EQ(pool.size(), before + 1);  // the residual; 0 - rest is there already
  EXPECT_EQ(with_negation, 1u);
  EXPECT_TRUE(minus_rest.valid());
  before = pool.size();
  EXPECT_EQ(SolveFor(&pool, pool.Sub(rest, x), x, false, &coefficient), rest);
  EXPECT_TRUE(pool.IsConst(coefficient, -1.0));
  EXPECT_EQ(pool.size(), before + 1);  // the residual only
  // A quotient or a function of other variables takes the general steps, which build its
  // derivative's factors: the same solution.
  const ExprId nonlinear = pool.Add(F(Op::kSin, y), pool.Div(z, y));
  EXPECT_EQ(SolveFor(&pool, pool.Sub(x, nonlinear), x, false, &coefficient), nonlinear);
  EXPECT_EQ(coefficient, pool.One());
  EXPECT_EQ(SolveFor(&pool, pool.Sub(nonlinear, x), x, false, &coefficient), nonlinear);
  // rest holding x itself: the general steps (x - (x/2 + y) = 0 => x = 2y).
  const ExprId sol = SolveFor(&pool, pool.Sub(x, pool.Add(pool.Div(x, C(2)), y)), x, false, &coefficient);
  ASSERT_TRUE(sol.valid());
  EXPECT_DOUBLE_EQ(Eval(sol, {0, 1.25, 0}), 2.5);
}

TEST_F(ExprAlgebraTest, SolveForParameterCoefficient) {
  ExprId coefficient;
  // p*x + y = 0: a parameter coefficient only when allowed; it is reported for the zero check.
  ExprId r = pool.Add(pool.Mul(p, x), y);
  EXPECT_FALSE(SolveFor(&pool, r, x, false, &coefficient).valid());
  ExprId sol = SolveFor(&pool, r, x, true, &coefficient);
  ASSERT_TRUE(sol.valid());
  EXPECT_EQ(coefficient, p);
  EXPECT_DOUBLE_EQ(Eval(sol, {0, 3, 0}), -3 / 1.5);
  // (p + q)*x - 2 = 0
  sol = SolveFor(&pool, pool.Sub(pool.Mul(pool.Add(p, q), x), C(2)), x, true, &coefficient);
  ASSERT_TRUE(sol.valid());
  EXPECT_DOUBLE_EQ(Eval(sol, {}), 2 / (1.5 - 0.5));
}

TEST_F(ExprAlgebraTest, SolveForRefusesNonlinearAndSingular) {
  ExprId c;
  EXPECT_FALSE(SolveFor(&pool, pool.Sub(pool.Mul(x, x), y), x, true, &c).valid());
  EXPECT_FALSE(SolveFor(&pool, pool.Sub(pool.Add(x, F(Op::kExp, x)), y), x, true, &c).valid());
  EXPECT_FALSE(SolveFor(&pool, pool.Sub(F(Op::kSin, x), y), x, true, &c).valid());
  // A variable coefficient: not solvable explicitly.
  EXPECT_FALSE(SolveFor(&pool, pool.Sub(pool.Mul(y, x), C(1)), x, true, &c).valid());
  // x does not occur (or cancels): coefficient zero.
  EXPECT_FALSE(SolveFor(&pool, pool.Sub(y, C(1)), x, true, &c).valid());
  EXPECT_FALSE(SolveFor(&pool, pool.Add(pool.Sub(x, x), y), x, true, &c).valid());
  EXPECT_FALSE(SolveFor(&pool, pool.Sub(pool.Mul(C(0), x), y), x, true, &c).valid());
  // x in an if-branch with a condition on x.
  EXPECT_FALSE(
      SolveFor(&pool, pool.If(pool.Binary(Op::kGt, x, C(0)), x, pool.Mul(C(2), x)), x, true, &c)
          .valid());
}

TEST_F(ExprAlgebraTest, SolveForIsExactWhenXAlsoOccursInAPiecewiseConstantTerm) {
  // x + sign(x) - 2 = 0 has the solution x = 1. d/dx sign(x) = 0 almost everywhere, so the
  // equation looks linear with coefficient 1, but x also occurs inside sign(): SolveFor must
  // either refuse or return a value that satisfies the equation. (Coulomb friction
  // f = c*v + f0*sign(v) solved for v is this case.)
  ExprId c;
  for (ExprId r : {pool.Sub(pool.Add(x, F(Op::kSign, x)), C(2)),
                   pool.Sub(pool.Add(x, pool.If(pool.Binary(Op::kGt, x, C(0)), C(1), C(0))), C(2))}) {
    ExprId sol = SolveFor(&pool, r, x, true, &c);
    if (!sol.valid()) continue;
    double xv = Eval(sol, {0, 0, 0});
    EXPECT_NEAR(Eval(r, {xv, 0, 0}), 0.0, 1e-12)
        << "SolveFor returned x = " << xv << ", which does not satisfy the equation";
  }
}

// ---------------------------------------------------------------------------------------------
// Printing

ExprNamer Names() {
  ExprNamer n;
  n.var = [](uint32_t v) { return std::string(1, "xyz"[v]); };
  n.param = [](uint32_t p) { return std::string(1, "pq"[p]); };
  return n;
}

/// Builds the pool expression of a parsed text over the names x, y, z, p, q.
ExprId FromAst(ExprPool* pool, const Ast& a) {
  ExprPool& P = *pool;
  auto sub = [&](size_t k) { return FromAst(pool, *a.args[k]); };
  switch (a.kind) {
    case Ast::Kind::kNumber:
    case Ast::Kind::kBool:
      return P.Const(a.number);
    case Ast::Kind::kName: {
      std::string n = a.PathText();
      if (n == "x") return P.Var(VarId(0u));
      if (n == "y") return P.Var(VarId(1u));
      if (n == "z") return P.Var(VarId(2u));
      if (n == "p") return P.Param(ParamId(0u));
      if (n == "q") return P.Param(ParamId(1u));
      if (n == "time") return P.Time();
      ADD_FAILURE() << "unknown name " << n;
      return P.Zero();
    }
    case Ast::Kind::kUnary:
      return a.op == "not" ? P.Unary(Op::kNot, sub(0)) : P.Neg(sub(0));
    case Ast::Kind::kBinary: {
      static const std::map<std::string, Op> ops = {
          {"+", Op::kAdd}, {"-", Op::kSub}, {"*", Op::kMul}, {"/", Op::kDiv}, {"^", Op::kPow},
          {"<", Op::kLt},  {"<=", Op::kLe}, {">", Op::kGt},  {">=", Op::kGe}, {"==", Op::kEq},
          {"<>", Op::kNe}, {"and", Op::kAnd}, {"or", Op::kOr}};
      ExprId r = sub(0);
      for (size_t k = 1; k < a.args.size(); ++k) r = P.Binary(ops.at(a.op), r, sub(k));
      return r;
    }
    case Ast::Kind::kSum:
    case Ast::Kind::kProduct: {
      ExprId r = sub(0);
      for (size_t k = 1; k < a.args.size(); ++k) {
        const char op = a.op[k];
        Op o = op == '+' ? Op::kAdd : op == '-' ? Op::kSub : op == '*' ? Op::kMul : Op::kDiv;
        r = P.Binary(o, r, sub(k));
      }
      return r;
    }
    case Ast::Kind::kIf: {
      ExprId r = sub(a.args.size() - 1);
      for (size_t k = a.args.size() - 1; k >= 2; k -= 2) r = P.If(sub(k - 2), sub(k - 1), r);
      return r;
    }
    case Ast::Kind::kCall: {
      static const std::map<std::string, Op> fns = {
          {"sin", Op::kSin},   {"cos", Op::kCos},     {"tan", Op::kTan},   {"asin", Op::kAsin},
          {"acos", Op::kAcos}, {"atan", Op::kAtan},   {"sinh", Op::kSinh}, {"cosh", Op::kCosh},
          {"tanh", Op::kTanh}, {"exp", Op::kExp},     {"log", Op::kLog},   {"log10", Op::kLog10},
          {"sqrt", Op::kSqrt}, {"abs", Op::kAbs},     {"sign", Op::kSign}, {"atan2", Op::kAtan2},
          {"min", Op::kMin},   {"max", Op::kMax}};
      if (a.op == "der") return P.Der(VarId(P.node(sub(0)).a));
      Op op = fns.at(a.op);
      return Arity(op) == 1 ? P.Unary(op, sub(0)) : P.Binary(op, sub(0), sub(1));
    }
  }
  return P.Zero();
}

TEST_F(ExprAlgebraTest, ToStringPrecedence) {
  ExprNamer n = Names();
  auto str = [&](ExprId e) { return ToString(pool, e, n); };
  EXPECT_EQ(str(pool.Mul(pool.Add(x, y), z)), "z * (x + y)");  // z sorts first
  EXPECT_EQ(str(pool.Add(x, pool.Mul(y, z))), "x + y * z");
  EXPECT_EQ(str(pool.Sub(x, pool.Sub(y, z))), "x - (y - z)");
  EXPECT_EQ(str(pool.Sub(pool.Sub(x, y), z)), "x - y - z");
  EXPECT_EQ(str(pool.Div(x, pool.Mul(y, z))), "x / (y * z)");
  EXPECT_EQ(str(pool.Pow(x, pool.Pow(y, z))), "x ^ y ^ z");
  EXPECT_EQ(str(pool.Pow(pool.Pow(x, y), z)), "(x ^ y) ^ z");
  EXPECT_EQ(str(pool.Neg(pool.Pow(x, C(2)))), "-x ^ 2");
  EXPECT_EQ(str(pool.Pow(pool.Neg(x), C(2))), "(-x) ^ 2");
  EXPECT_EQ(str(pool.Neg(pool.Add(x, y))), "-(x + y)");
  EXPECT_EQ(str(F(Op::kAtan2, x, pool.Add(y, p))), "atan2(x, y + p)");
  EXPECT_EQ(str(pool.Der(VarId(1u))), "der(y)");
  EXPECT_EQ(str(pool.Add(pool.If(pool.Binary(Op::kLt, x, y), x, y), z)),
            "z + (if x < y then x else y)");
  EXPECT_EQ(str(pool.Unary(Op::kNot, pool.Binary(Op::kAnd, pool.Binary(Op::kLt, x, y),
                                                 pool.Binary(Op::kGt, z, p)))),
            "not (x < y and z > p)");
  EXPECT_EQ(str(pool.Mul(pool.Time(), C(-2.5))), "time * -2.5");
}

TEST_F(ExprAlgebraTest, ToStringElidesDeepTrees) {
  ExprId e = x;
  for (int k = 0; k < 100000; ++k) e = pool.Add(pool.Mul(e, y), C(k + 1));
  std::string s = ToString(pool, e, Names());
  EXPECT_NE(s.find("…"), std::string::npos);
  EXPECT_LT(s.size(), 10000u);
}

TEST_F(ExprAlgebraTest, ToStringRoundTripsThroughTheParser) {
  // Hand-picked shapes where parentheses matter, then random expressions.
  std::vector<ExprId> cases = {
      pool.Sub(x, pool.Add(y, z)),
      pool.Div(x, pool.Div(y, z)),
      pool.Pow(x, pool.Neg(y)),
      pool.Pow(pool.Add(x, C(1)), pool.Pow(y, C(2))),
      pool.Neg(pool.Pow(x, y)),
      pool.Mul(pool.Neg(x), pool.Pow(y, C(3))),
      pool.Binary(Op::kOr, pool.Binary(Op::kAnd, pool.Binary(Op::kLt, x, y), pool.Binary(Op::kGe, y, z)),
                  pool.Unary(Op::kNot, pool.Binary(Op::kEq, x, z))),
      pool.If(pool.If(pool.Binary(Op::kLt, x, y), pool.Binary(Op::kGt, z, C(0)), pool.Binary(Op::kLt, z, C(0))), x,
              pool.If(pool.Binary(Op::kNe, x, p), y, z)),
      pool.Sub(x, pool.Const(-2)),
      pool.Mul(pool.Const(-2), x),
      pool.Pow(x, pool.Const(-2)),
      pool.Pow(pool.Const(-2), x),  // a negative base must keep its parentheses
      // Relations do not chain: (x > 0) == (y > 0) needs its parentheses.
      pool.Binary(Op::kEq, pool.Binary(Op::kGt, x, C(0)), pool.Binary(Op::kGt, y, C(0))),
  };
  std::mt19937 rng(11);
  std::function<ExprId(int)> gen = [&](int depth) -> ExprId {
    std::uniform_int_distribution<int> pick(0, depth <= 0 ? 3 : 14);
    switch (pick(rng)) {
      case 0: return pool.Var(VarId(static_cast<uint32_t>(rng() % 3)));
      case 1: return pool.Param(ParamId(static_cast<uint32_t>(rng() % 2)));
      case 2: return C(static_cast<double>(rng() % 7 + 1) / 2);
      case 3: return pool.Time();
      case 4: return pool.Add(gen(depth - 1), gen(depth - 1));
      case 5: return pool.Sub(gen(depth - 1), gen(depth - 1));
      case 6: return pool.Mul(gen(depth - 1), gen(depth - 1));
      case 7: return pool.Div(gen(depth - 1), gen(depth - 1));
      case 8: return pool.Pow(pool.Add(C(2), pool.Mul(x, x)), gen(depth - 1));
      case 9: return pool.Neg(gen(depth - 1));
      case 10: return F(Op::kSin, gen(depth - 1));
      case 11: return F(Op::kAtan2, gen(depth - 1), gen(depth - 1));
      case 12: return pool.If(pool.Binary(Op::kLt, gen(depth - 1), gen(depth - 1)), gen(depth - 1), gen(depth - 1));
      case 13: return pool.Binary(Op::kMax, gen(depth - 1), gen(depth - 1));
      default: return pool.Sub(pool.Pow(gen(depth - 1), C(2)), gen(depth - 1));
    }
  };
  // Random expressions whose constants print exactly (folded sin(1.5) does not at 15 digits).
  auto exactly_printable = [&](ExprId root) {
    std::vector<ExprId> stack{root};
    while (!stack.empty()) {
      const Node& nd = pool.node(stack.back());
      stack.pop_back();
      if (nd.op == Op::kConst) {
        char buf[64];
        std::snprintf(buf, sizeof buf, "%.15g", nd.value());
        if (std::strtod(buf, nullptr) != nd.value()) return false;
      }
      if (Arity(nd.op) >= 1) stack.push_back(ExprId(nd.a));
      if (Arity(nd.op) >= 2) stack.push_back(ExprId(nd.b));
      if (Arity(nd.op) >= 3) stack.push_back(ExprId(nd.c));
    }
    return true;
  };
  int random_cases = 0;
  while (random_cases < 200) {
    ExprId e = gen(5);
    if (!exactly_printable(e)) continue;
    cases.push_back(e);
    ++random_cases;
  }
  ExprNamer n = Names();
  SourceLoc loc{"m.yaml", 1, 1};
  for (ExprId e : cases) {
    std::string text = ToString(pool, e, n);
    AstPtr ast;
    try {
      ast = ParseExpression(text, loc);
    } catch (const ModelError& err) {
      ADD_FAILURE() << "'" << text << "' does not parse: " << err.what();
      continue;
    }
    ExprId back = FromAst(&pool, *ast);
    // The same value, and the same node (hash-consing makes that the test of equal structure).
    std::vector<double> vars = {0.7, -1.3, 0.4};
    double want = Eval(e, vars, {1.5, -0.5}, 0.6), got = Eval(back, vars, {1.5, -0.5}, 0.6);
    if (std::isnan(want)) {
      EXPECT_TRUE(std::isnan(got)) << text;
    } else {
      EXPECT_NEAR(got, want, 1e-12 * std::max(1.0, std::fabs(want))) << text;
    }
    EXPECT_EQ(back, e) << text;
  }
}

}  // namespace
}  // namespace momenta
