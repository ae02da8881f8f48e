// The expression pool: hash-consing, canonical order of commutative operations, constant folding
// and the algebraic identities its constructors apply, if with a constant condition, noEvent
// flags and the leaf-kind masks.

#include "core/expr/expr.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "core/expr/expr_eval.h"

namespace momenta {
namespace {

class ExprTest : public ::testing::Test {
 protected:
  ExprPool pool;
  ExprId x = pool.Var(VarId(0u));
  ExprId y = pool.Var(VarId(1u));
  ExprId z = pool.Var(VarId(2u));
  ExprId p = pool.Param(ParamId(0u));
  ExprId q = pool.Param(ParamId(1u));

  double Eval(ExprId e, std::vector<double> vars, std::vector<double> params = {}) {
    LeafValues lv;
    lv.vars = vars.data();
    lv.params = params.empty() ? nullptr : params.data();
    return Evaluate(pool, e, lv);
  }
};

TEST_F(ExprTest, SameStructureIsSameNode) {
  ExprId a = pool.Unary(Op::kSin, pool.Add(x, pool.Const(2.0)));
  ExprId b = pool.Unary(Op::kSin, pool.Add(x, pool.Const(2.0)));
  EXPECT_EQ(a, b);
  EXPECT_EQ(pool.Var(VarId(0u)), x);
  EXPECT_EQ(pool.Const(2.5), pool.Const(2.5));
  EXPECT_NE(pool.Const(2.5), pool.Const(2.5000000001));
  // Leaves of different kinds with the same payload are different nodes.
  EXPECT_NE(pool.Var(VarId(3u)), pool.Der(VarId(3u)));
  EXPECT_NE(pool.Var(VarId(3u)), pool.Pre(VarId(3u)));
  EXPECT_NE(pool.Var(VarId(3u)), pool.Param(ParamId(3u)));
  // Building the same thing twice adds no node.
  size_t before = pool.size();
  pool.Unary(Op::kSin, pool.Add(x, pool.Const(2.0)));
  EXPECT_EQ(pool.size(), before);
}

TEST_F(ExprTest, LeavesFoundByVariableAreTheInternedOnes) {
  // FindLeaf answers for x, pre(x), der(x) from tables by variable: exactly the leaves made.
  EXPECT_EQ(pool.FindLeaf(Op::kVar, 1), y);
  EXPECT_FALSE(pool.FindLeaf(Op::kVar, 7).valid());
  EXPECT_FALSE(pool.FindLeaf(Op::kDer, 0).valid());
  EXPECT_FALSE(pool.FindLeaf(Op::kPre, 1).valid());
  const size_t nodes = pool.size();
  ExprId dx = pool.Der(VarId(0u)), ddx = pool.Der(VarId(0u), 2), pre = pool.Pre(VarId(1u));
  EXPECT_EQ(pool.size(), nodes + 3);
  EXPECT_EQ(pool.Der(VarId(0u)), dx);
  EXPECT_EQ(pool.Der(VarId(0u), 2), ddx);
  EXPECT_NE(dx, ddx);
  EXPECT_EQ(pool.DerOrder(ddx), 2u);
  EXPECT_EQ(pool.Pre(VarId(1u)), pre);
  EXPECT_EQ(pool.Var(VarId(1u)), y);
  EXPECT_EQ(pool.size(), nodes + 3);
  EXPECT_EQ(pool.FindLeaf(Op::kDer, 0), dx);
  EXPECT_EQ(pool.FindLeaf(Op::kPre, 1), pre);
  EXPECT_EQ(pool.FindLeaf(Op::kParam, 0), p);
  EXPECT_FALSE(pool.FindLeaf(Op::kPre, 0).valid());
  // A variable far beyond those seen so far.
  ExprId far = pool.Var(VarId(100000u));
  EXPECT_EQ(pool.FindLeaf(Op::kVar, 100000), far);
  EXPECT_EQ(pool.node(far).a, 100000u);
}

TEST_F(ExprTest, CommutativeOperationsHaveOneCanonicalOrder) {
  EXPECT_EQ(pool.Add(x, y), pool.Add(y, x));
  EXPECT_EQ(pool.Mul(x, y), pool.Mul(y, x));
  EXPECT_EQ(pool.Binary(Op::kMin, x, y), pool.Binary(Op::kMin, y, x));
  EXPECT_EQ(pool.Binary(Op::kMax, x, y), pool.Binary(Op::kMax, y, x));
  EXPECT_EQ(pool.Binary(Op::kEq, x, y), pool.Binary(Op::kEq, y, x));
  EXPECT_EQ(pool.Binary(Op::kNe, x, y), pool.Binary(Op::kNe, y, x));
  ExprId bx = pool.Binary(Op::kLt, x, y), by = pool.Binary(Op::kLt, y, x);
  EXPECT_EQ(pool.Binary(Op::kAnd, bx, by), pool.Binary(Op::kAnd, by, bx));
  EXPECT_EQ(pool.Binary(Op::kOr, bx, by), pool.Binary(Op::kOr, by, bx));
  // Not commutative: the order is kept.
  EXPECT_NE(pool.Sub(x, y), pool.Sub(y, x));
  EXPECT_NE(pool.Div(x, y), pool.Div(y, x));
  EXPECT_NE(pool.Pow(x, y), pool.Pow(y, x));
  EXPECT_NE(bx, by);
  EXPECT_NE(pool.Binary(Op::kAtan2, x, y), pool.Binary(Op::kAtan2, y, x));
  EXPECT_DOUBLE_EQ(Eval(pool.Sub(x, y), {5, 2}), 3.0);
  EXPECT_DOUBLE_EQ(Eval(pool.Sub(y, x), {5, 2}), -3.0);
}

TEST_F(ExprTest, ConstantsFold) {
  EXPECT_TRUE(pool.IsConst(pool.Add(pool.Const(2), pool.Const(3)), 5.0));
  EXPECT_TRUE(pool.IsConst(pool.Mul(pool.Const(2), pool.Const(3)), 6.0));
  EXPECT_TRUE(pool.IsConst(pool.Sub(pool.Const(2), pool.Const(3)), -1.0));
  EXPECT_TRUE(pool.IsConst(pool.Div(pool.Const(3), pool.Const(2)), 1.5));
  EXPECT_TRUE(pool.IsConst(pool.Pow(pool.Const(2), pool.Const(10)), 1024.0));
  EXPECT_TRUE(pool.IsConst(pool.Unary(Op::kSin, pool.Const(0)), 0.0));
  EXPECT_TRUE(pool.IsConst(pool.Unary(Op::kExp, pool.Const(0)), 1.0));
  EXPECT_TRUE(pool.IsConst(pool.Unary(Op::kAbs, pool.Const(-4)), 4.0));
  EXPECT_TRUE(pool.IsConst(pool.Unary(Op::kSign, pool.Const(-4)), -1.0));
  EXPECT_TRUE(pool.IsConst(pool.Unary(Op::kFloor, pool.Const(-1.1)), -2.0));  // towards -inf
  EXPECT_TRUE(pool.IsConst(pool.Unary(Op::kFloor, pool.Const(2.9)), 2.0));
  EXPECT_TRUE(pool.IsConst(pool.Binary(Op::kAtan2, pool.Const(1), pool.Const(1)), M_PI / 4));
  EXPECT_TRUE(pool.IsConst(pool.Binary(Op::kMin, pool.Const(1), pool.Const(-1)), -1.0));
  EXPECT_TRUE(pool.IsConst(pool.Binary(Op::kLt, pool.Const(2), pool.Const(3)), 1.0));
  EXPECT_TRUE(pool.IsConst(pool.Binary(Op::kGe, pool.Const(2), pool.Const(3)), 0.0));
  EXPECT_TRUE(pool.IsConst(pool.Unary(Op::kNot, pool.Const(0)), 1.0));
  EXPECT_TRUE(pool.IsConst(pool.Neg(pool.Const(2)), -2.0));
  // One zero: -0 is the same node as 0.
  EXPECT_EQ(pool.Const(-0.0), pool.Zero());
  EXPECT_EQ(pool.Neg(pool.Zero()), pool.Zero());
  EXPECT_EQ(pool.Const(0.0), pool.Zero());
  EXPECT_EQ(pool.Const(1.0), pool.One());
}

TEST_F(ExprTest, DivisionByZeroStaysSymbolic) {
  // Not a folded inf: the node stays, marked singular, for the build to name it at its line.
  ExprId e = pool.Div(pool.Const(1), pool.Const(0));
  EXPECT_FALSE(pool.IsConst(e));
  EXPECT_EQ(pool.op(e), Op::kDiv);
  EXPECT_TRUE(std::isinf(Eval(e, {})));
}

TEST_F(ExprTest, ZeroToANegativePowerStaysSymbolic) {
  // 0^-1 is inf: kept as a node, like x/0, for the build to name.
  ExprId e = pool.Pow(pool.Const(0), pool.Const(-1));
  EXPECT_FALSE(pool.IsConst(e)) << "0^-1 was folded to " << pool.ConstValue(e);
}

TEST_F(ExprTest, NonFiniteOperationsOnConstantsAreKeptAndMarked) {
  // Each stays a node marked singular, for the build to name; none folds to 0 (or to inf).
  const ExprId inf = pool.Div(pool.Const(1), pool.Const(0));
  const ExprId nan = pool.Div(pool.Const(0), pool.Const(0));
  EXPECT_TRUE(pool.IsSingular(inf));
  EXPECT_TRUE(pool.IsSingular(nan));
  EXPECT_TRUE(std::isnan(Eval(nan, {})));
  EXPECT_TRUE(pool.IsSingular(pool.Mul(pool.Const(1e308), pool.Const(10))));
  EXPECT_TRUE(pool.IsSingular(pool.Unary(Op::kSqrt, pool.Const(-1))));
  EXPECT_TRUE(pool.IsSingular(pool.Unary(Op::kLog, pool.Const(0))));
  // The identities that would drop such an operand do not apply to it: 0*(1/0), (1/0)*0,
  // 0/(0/0), (1/0)-(1/0) are NaN, not 0; (0/0)^0 is kept too, for the build to name.
  for (ExprId e : {pool.Mul(pool.Zero(), inf), pool.Mul(inf, pool.Zero()), pool.Div(pool.Zero(), nan),
                   pool.Sub(inf, inf)}) {
    EXPECT_FALSE(pool.IsConst(e));
    EXPECT_TRUE(pool.IsSingular(e));
    EXPECT_TRUE(std::isnan(Eval(e, {})));
  }
  EXPECT_TRUE(pool.IsSingular(pool.Pow(nan, pool.Zero())));
  // (x-x)/(x-x): x - x is 0 for a finite x, and 0/0 is not folded.
  const ExprId d = pool.Div(pool.Sub(x, x), pool.Sub(x, x));
  EXPECT_TRUE(pool.IsSingular(d));
  EXPECT_TRUE(std::isnan(Eval(d, {2.0})));
  // Finite operands keep every identity, and finite folds are unmarked.
  EXPECT_EQ(pool.Mul(x, pool.Zero()), pool.Zero());
  EXPECT_EQ(pool.Div(pool.Zero(), x), pool.Zero());
  EXPECT_EQ(pool.Sub(x, x), pool.Zero());
  EXPECT_EQ(pool.Pow(x, pool.Zero()), pool.One());
  EXPECT_FALSE(pool.IsSingular(pool.Mul(pool.Const(1e300), pool.Const(10))));
  // A division by the constant zero is one whatever the numerator.
  EXPECT_TRUE(pool.IsSingular(pool.Div(x, pool.Sub(y, y))));
  EXPECT_FALSE(pool.IsSingular(pool.Div(x, y)));
}

TEST_F(ExprTest, Identities) {
  ExprId zero = pool.Zero(), one = pool.One();
  EXPECT_EQ(pool.Add(x, zero), x);
  EXPECT_EQ(pool.Add(zero, x), x);
  EXPECT_EQ(pool.Sub(x, zero), x);
  EXPECT_EQ(pool.Sub(zero, x), pool.Neg(x));
  EXPECT_EQ(pool.Mul(x, one), x);
  EXPECT_EQ(pool.Mul(one, x), x);
  EXPECT_EQ(pool.Mul(x, zero), zero);
  EXPECT_EQ(pool.Mul(zero, pool.Unary(Op::kSin, x)), zero);
  EXPECT_EQ(pool.Mul(pool.Const(-1), x), pool.Neg(x));
  EXPECT_EQ(pool.Mul(x, pool.Const(-1)), pool.Neg(x));
  EXPECT_EQ(pool.Div(x, one), x);
  EXPECT_EQ(pool.Div(x, pool.Const(-1)), pool.Neg(x));
  EXPECT_EQ(pool.Div(zero, x), zero);
  EXPECT_EQ(pool.Pow(x, one), x);
  EXPECT_EQ(pool.Pow(x, zero), one);
  EXPECT_EQ(pool.Neg(pool.Neg(x)), x);
  EXPECT_EQ(pool.Sub(x, x), zero);
  ExprId s = pool.Unary(Op::kSin, pool.Mul(x, y));
  EXPECT_EQ(pool.Sub(s, s), zero);
  EXPECT_EQ(pool.Unary(Op::kNot, pool.Unary(Op::kNot, pool.Binary(Op::kLt, x, y))),
            pool.Binary(Op::kLt, x, y));
}

TEST_F(ExprTest, NegationsAreAbsorbed) {
  EXPECT_EQ(pool.Add(x, pool.Neg(y)), pool.Sub(x, y));
  EXPECT_EQ(pool.Add(pool.Neg(x), y), pool.Sub(y, x));
  EXPECT_EQ(pool.Sub(x, pool.Neg(y)), pool.Add(x, y));
  EXPECT_EQ(pool.Neg(pool.Sub(x, y)), pool.Sub(y, x));
  EXPECT_EQ(pool.Mul(pool.Neg(x), pool.Neg(y)), pool.Mul(x, y));
  EXPECT_EQ(pool.Mul(pool.Neg(x), y), pool.Neg(pool.Mul(x, y)));
  EXPECT_EQ(pool.Mul(x, pool.Neg(y)), pool.Neg(pool.Mul(x, y)));
  EXPECT_EQ(pool.Div(pool.Neg(x), y), pool.Neg(pool.Div(x, y)));
  // And the values are right.
  const std::vector<double> v = {1.5, -2.25};
  EXPECT_DOUBLE_EQ(Eval(pool.Add(x, pool.Neg(y)), v), 1.5 + 2.25);
  EXPECT_DOUBLE_EQ(Eval(pool.Mul(pool.Neg(x), y), v), 1.5 * 2.25);
  EXPECT_DOUBLE_EQ(Eval(pool.Neg(pool.Sub(x, y)), v), -(1.5 + 2.25));
}

TEST_F(ExprTest, FoldingAgreesWithEvaluationOfLogic) {
  // The constructors' shortcuts for and/or/not must give the value ApplyBinary/ApplyUnary give
  // (0 or 1) whatever the operand: `x and true` is 1 for x = 2.5, not 2.5.
  const std::vector<double> v = {2.5, -3.0};
  ExprId t = pool.One(), f = pool.Zero();
  EXPECT_DOUBLE_EQ(Eval(pool.Binary(Op::kAnd, x, t), v), ApplyBinary(Op::kAnd, 2.5, 1.0));
  EXPECT_DOUBLE_EQ(Eval(pool.Binary(Op::kAnd, t, x), v), ApplyBinary(Op::kAnd, 1.0, 2.5));
  EXPECT_DOUBLE_EQ(Eval(pool.Binary(Op::kAnd, f, x), v), 0.0);
  EXPECT_DOUBLE_EQ(Eval(pool.Binary(Op::kOr, x, f), v), ApplyBinary(Op::kOr, 2.5, 0.0));
  EXPECT_DOUBLE_EQ(Eval(pool.Binary(Op::kOr, t, x), v), 1.0);
  EXPECT_DOUBLE_EQ(Eval(pool.Unary(Op::kNot, pool.Unary(Op::kNot, y)), v),
                   ApplyUnary(Op::kNot, ApplyUnary(Op::kNot, -3.0)));
}

TEST_F(ExprTest, IfWithConstantCondition) {
  ExprId a = pool.Unary(Op::kSin, x), b = pool.Unary(Op::kCos, x);
  EXPECT_EQ(pool.If(pool.One(), a, b), a);
  EXPECT_EQ(pool.If(pool.Zero(), a, b), b);
  EXPECT_EQ(pool.If(pool.Const(-2), a, b), a);
  // A condition that folds to a constant.
  EXPECT_EQ(pool.If(pool.Binary(Op::kLt, pool.Const(3), pool.Const(2)), a, b), b);
  // Equal branches: the condition does not matter.
  EXPECT_EQ(pool.If(pool.Binary(Op::kLt, x, y), a, a), a);
  // A variable condition stays.
  ExprId c = pool.If(pool.Binary(Op::kLt, x, y), a, b);
  EXPECT_EQ(pool.op(c), Op::kIf);
  EXPECT_DOUBLE_EQ(Eval(c, {0.5, 1.0}), std::sin(0.5));
  EXPECT_DOUBLE_EQ(Eval(c, {1.5, 1.0}), std::cos(1.5));
}

TEST_F(ExprTest, NoEventFlagsEveryRelation) {
  ExprId lt = pool.Binary(Op::kLt, x, y);
  ExprId gt = pool.Binary(Op::kGt, x, pool.Const(1));
  ExprId e = pool.Add(pool.If(pool.Binary(Op::kAnd, lt, gt), x, y), pool.Unary(Op::kSin, z));
  ExprId ne = pool.NoEvent(e);
  EXPECT_NE(ne, e);
  // Every relation below carries the flag; the original nodes are untouched.
  int relations = 0;
  std::vector<ExprId> stack{ne};
  while (!stack.empty()) {
    ExprId id = stack.back();
    stack.pop_back();
    const Node& n = pool.node(id);
    if (IsRelation(n.op)) {
      ++relations;
      EXPECT_TRUE(n.flags & kNoEvent) << OpName(n.op);
    }
    if (Arity(n.op) >= 1) stack.push_back(ExprId(n.a));
    if (Arity(n.op) >= 2) stack.push_back(ExprId(n.b));
    if (Arity(n.op) >= 3) stack.push_back(ExprId(n.c));
  }
  EXPECT_EQ(relations, 2);
  EXPECT_FALSE(pool.node(lt).flags & kNoEvent);
  // Same value.
  for (double xv : {0.0, 1.5, 3.0}) {
    EXPECT_DOUBLE_EQ(Eval(ne, {xv, 2.0, 0.3}), Eval(e, {xv, 2.0, 0.3}));
  }
  // Idempotent, hash-consed, and a no-op without relations.
  EXPECT_EQ(pool.NoEvent(ne), ne);
  EXPECT_EQ(pool.NoEvent(e), ne);
  ExprId plain = pool.Mul(x, pool.Unary(Op::kExp, y));
  EXPECT_EQ(pool.NoEvent(plain), plain);
  // The flag is part of the node's identity for relations only.
  EXPECT_NE(pool.Binary(Op::kLt, x, y, kNoEvent), lt);
  EXPECT_EQ(pool.Binary(Op::kLt, x, y, kNoEvent), pool.NoEvent(lt));
  EXPECT_EQ(pool.Binary(Op::kAdd, x, y, kNoEvent), pool.Add(x, y));
}

TEST_F(ExprTest, LeafMasks) {
  EXPECT_EQ(pool.mask(x), kHasVar);
  EXPECT_EQ(pool.mask(pool.Der(VarId(0u))), kHasDer);
  EXPECT_EQ(pool.mask(pool.Pre(VarId(0u))), kHasPre);
  EXPECT_EQ(pool.mask(p), kHasParam);
  EXPECT_EQ(pool.mask(pool.Time()), kHasTime);
  EXPECT_EQ(pool.mask(pool.Initial()), kHasInitial);
  EXPECT_EQ(pool.mask(pool.Const(3)), 0);
  ExprId e = pool.Add(pool.Mul(p, x), pool.Unary(Op::kSin, pool.Der(VarId(1u))));
  EXPECT_EQ(pool.mask(e), kHasVar | kHasParam | kHasDer);
  ExprId rel = pool.If(pool.Binary(Op::kGt, pool.Time(), p), q, pool.Const(2));
  EXPECT_EQ(pool.mask(rel), kHasTime | kHasParam | kHasRelation);
  // IsParamOnly: parameters and constants only.
  EXPECT_TRUE(pool.IsParamOnly(pool.Const(2)));
  EXPECT_TRUE(pool.IsParamOnly(p));
  EXPECT_TRUE(pool.IsParamOnly(pool.Div(pool.Unary(Op::kSqrt, p), pool.Add(q, pool.Const(1)))));
  EXPECT_TRUE(pool.IsParamOnly(pool.If(pool.Binary(Op::kLt, p, q), p, q)));
  EXPECT_FALSE(pool.IsParamOnly(x));
  EXPECT_FALSE(pool.IsParamOnly(pool.Mul(p, x)));
  EXPECT_FALSE(pool.IsParamOnly(pool.Time()));
  EXPECT_FALSE(pool.IsParamOnly(pool.Add(p, pool.Time())));
  EXPECT_FALSE(pool.IsParamOnly(pool.Pre(VarId(0u))));
  EXPECT_FALSE(pool.IsParamOnly(pool.Der(VarId(0u))));
  EXPECT_FALSE(pool.IsParamOnly(pool.Initial()));
  EXPECT_FALSE(pool.IsParamOnly(pool.Cj()));
  // Folding away the variable makes it parameter-only again.
  EXPECT_TRUE(pool.IsParamOnly(pool.Add(p, pool.Sub(x, x))));
}

TEST_F(ExprTest, FindLeafDoesNotCreate) {
  size_t before = pool.size();
  EXPECT_FALSE(pool.FindLeaf(Op::kDer, 77).valid());
  EXPECT_FALSE(pool.FindLeaf(Op::kVar, 77).valid());
  EXPECT_EQ(pool.size(), before);
  ExprId d = pool.Der(VarId(77u));
  EXPECT_EQ(pool.FindLeaf(Op::kDer, 77), d);
  EXPECT_FALSE(pool.FindLeaf(Op::kVar, 77).valid());
  EXPECT_EQ(pool.FindLeaf(Op::kVar, 0), x);
  EXPECT_EQ(pool.FindLeaf(Op::kParam, 1), q);
}

TEST_F(ExprTest, OperationTables) {
  EXPECT_EQ(Arity(Op::kConst), 0);
  EXPECT_EQ(Arity(Op::kCj), 0);
  EXPECT_EQ(Arity(Op::kNeg), 1);
  EXPECT_EQ(Arity(Op::kSign), 1);
  EXPECT_EQ(Arity(Op::kNot), 1);
  EXPECT_EQ(Arity(Op::kAtan2), 2);
  EXPECT_EQ(Arity(Op::kOr), 2);
  EXPECT_EQ(Arity(Op::kIf), 3);
  EXPECT_TRUE(IsLeaf(Op::kParam));
  EXPECT_FALSE(IsLeaf(Op::kAdd));
  for (Op op : {Op::kLt, Op::kLe, Op::kGt, Op::kGe, Op::kEq, Op::kNe}) {
    EXPECT_TRUE(IsRelation(op)) << OpName(op);
    EXPECT_TRUE(IsBooleanOp(op)) << OpName(op);
  }
  EXPECT_FALSE(IsRelation(Op::kAnd));
  EXPECT_TRUE(IsBooleanOp(Op::kAnd));
  EXPECT_TRUE(IsBooleanOp(Op::kNot));
  EXPECT_FALSE(IsBooleanOp(Op::kMin));
  EXPECT_STREQ(OpName(Op::kNe), "<>");
  EXPECT_STREQ(OpName(Op::kAtan2), "atan2");
}

TEST_F(ExprTest, ManyNodesSurviveTableGrowth) {
  // Far more nodes than the initial table: ids stay stable and lookups find them again.
  std::vector<ExprId> ids;
  for (int k = 0; k < 50000; ++k) ids.push_back(pool.Add(pool.Var(VarId(static_cast<uint32_t>(k))), pool.Const(k + 0.5)));
  size_t size = pool.size();
  for (int k = 0; k < 50000; ++k) {
    ASSERT_EQ(pool.Add(pool.Const(k + 0.5), pool.Var(VarId(static_cast<uint32_t>(k)))), ids[k]) << k;
  }
  EXPECT_EQ(pool.size(), size);
  // The constant operand of one of them has its value.
  const Node& n = pool.node(ids[1234]);
  ExprId c = pool.IsConst(ExprId(n.a)) ? ExprId(n.a) : ExprId(n.b);
  EXPECT_TRUE(pool.IsConst(c, 1234.5));
}

TEST_F(ExprTest, NodesAreFoundWhetherJustMadeOrMovedToTheMainTable) {
  // A node whose child was made a moment ago is looked for among the newest nodes only (the
  // nursery); one over older children in the main table too. Either way an equal node is the
  // same node, before and after the nursery moves its entries to the main table.
  const ExprId cond = pool.Cond(3);  // a leaf found by hash, not by index
  const ExprId d2 = pool.Der(VarId(5u), 2);
  std::vector<ExprId> sums;
  for (uint32_t k = 0; k < 20000; ++k) {
    const ExprId product = pool.Mul(pool.Var(VarId(k)), pool.Const(k + 0.25));
    sums.push_back(pool.Add(product, d2));
    ASSERT_EQ(pool.Add(d2, pool.Mul(pool.Const(k + 0.25), pool.Var(VarId(k)))), sums.back()) << k;
  }
  const size_t size = pool.size();
  for (uint32_t k = 0; k < 20000; ++k) {
    ASSERT_EQ(pool.Add(pool.Mul(pool.Const(k + 0.25), pool.Var(VarId(k))), d2), sums[k]) << k;
  }
  EXPECT_EQ(pool.size(), size);
  EXPECT_EQ(pool.FindLeaf(Op::kCond, 3), cond);
  EXPECT_FALSE(pool.FindLeaf(Op::kCond, 4).valid());
  EXPECT_EQ(pool.Der(VarId(5u), 2), d2);
}

TEST_F(ExprTest, EvaluateReadsEveryLeafKind) {
  std::vector<double> vars = {1, 2, 3}, ders = {10, 20, 30}, pres = {-1, -2, -3}, params = {7, 8};
  LeafValues lv;
  lv.vars = vars.data();
  lv.ders = ders.data();
  lv.pres = pres.data();
  lv.params = params.data();
  lv.time = 0.25;
  lv.initial = true;
  EXPECT_EQ(Evaluate(pool, y, lv), 2);
  EXPECT_EQ(Evaluate(pool, pool.Der(VarId(2u)), lv), 30);
  EXPECT_EQ(Evaluate(pool, pool.Pre(VarId(0u)), lv), -1);
  EXPECT_EQ(Evaluate(pool, q, lv), 8);
  EXPECT_EQ(Evaluate(pool, pool.Time(), lv), 0.25);
  EXPECT_EQ(Evaluate(pool, pool.Initial(), lv), 1.0);
  // pre() without pre-values reads the variable.
  lv.pres = nullptr;
  EXPECT_EQ(Evaluate(pool, pool.Pre(VarId(1u)), lv), 2);
}

}  // namespace
}  // namespace momenta
