// The equations' leaves as the rounds of alias elimination and index reduction keep them:
// CollectLeaves, whose walk of a small tree does not remember inner nodes, against a walk that
// remembers them (the same leaves, also for shared subtrees and past the walk's budgets, in an
// order of what they are that does not follow node ids), and EquationLeaves' answers against the
// substitution's own walk as equations are rewritten and dropped.

#include "core/passes/equation_system.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <string>
#include <tuple>
#include <vector>

namespace momenta {
namespace {

constexpr uint8_t kAllLeaves = kHasVar | kHasDer | kHasPre | kHasParam;

/// A random expression over a few variables, derivatives, pre-values and parameters, built so that
/// subtrees are shared (each new node takes its operands from all made so far).
ExprId RandomExpression(ExprPool* p, std::mt19937* rng, int nodes, int num_vars) {
  std::vector<ExprId> made;
  std::uniform_int_distribution<int> var(0, num_vars - 1), kind(0, 4);
  for (int k = 0; k < 6; ++k) {
    const VarId v(static_cast<uint32_t>(var(*rng)));
    switch (kind(*rng)) {
      case 0: made.push_back(p->Var(v)); break;
      case 1: made.push_back(p->Der(v)); break;
      case 2: made.push_back(p->Pre(v)); break;
      case 3: made.push_back(p->Param(ParamId(v.value()))); break;
      default: made.push_back(p->Const(1.5 + k)); break;
    }
  }
  const Op ops[] = {Op::kAdd, Op::kSub, Op::kMul, Op::kDiv};
  std::uniform_int_distribution<int> op(0, 3), leaf(0, 4);
  for (int k = 0; k < nodes; ++k) {
    std::uniform_int_distribution<size_t> pick(0, made.size() - 1);
    ExprId a = made[pick(*rng)], b = made[pick(*rng)];
    // Now and then a fresh leaf, so that leaves keep coming as the expression grows.
    if (leaf(*rng) == 0) a = p->Var(VarId(static_cast<uint32_t>(var(*rng))));
    made.push_back(p->Binary(ops[op(*rng)], a, b));
  }
  return made.back();
}

/// The leaves as a depth-first walk that visits each node once finds them (children pushed a, b,
/// c, the last popped first), then sorted by variable (or parameter) index, kind and derivative
/// order: CollectLeaves' list in its order.
std::vector<ExprId> RememberedWalkLeaves(const ExprPool& p, ExprId e, uint8_t mask) {
  std::vector<ExprId> leaves;
  std::vector<bool> seen(p.size(), false);
  std::vector<uint32_t> stack{e.value()};
  while (!stack.empty()) {
    const uint32_t id = stack.back();
    stack.pop_back();
    const Node& n = p.node(ExprId(id));
    if (!(n.mask & mask) || seen[id]) continue;
    seen[id] = true;
    if (n.op == Op::kVar || n.op == Op::kDer || n.op == Op::kPre || n.op == Op::kParam) {
      leaves.push_back(ExprId(id));
      continue;
    }
    const int arity = Arity(n.op);
    if (arity >= 1) stack.push_back(n.a);
    if (arity >= 2) stack.push_back(n.b);
    if (arity >= 3) stack.push_back(n.c);
  }
  std::sort(leaves.begin(), leaves.end(), [&](ExprId x, ExprId y) {
    const Node &a = p.node(x), &b = p.node(y);
    return std::make_tuple(a.a, a.op, a.b) < std::make_tuple(b.a, b.op, b.b);
  });
  return leaves;
}

TEST(CollectLeavesTest, SameLeavesAsARememberedWalkInLeafOrder) {
  ExprPool p;
  std::mt19937 rng(7);
  std::vector<ExprId> fast, reference;
  // Small trees (the walk's own path), large and much shared ones (handed over), few and many
  // distinct leaves (past the leaf budget).
  for (int nodes : {1, 3, 8, 20, 60, 300, 2000}) {
    for (int num_vars : {2, 10, 200}) {
      for (int trial = 0; trial < 20; ++trial) {
        const ExprId e = RandomExpression(&p, &rng, nodes, num_vars);
        for (uint8_t mask : {kAllLeaves, uint8_t(kHasVar), uint8_t(kHasDer), uint8_t(kHasVar | kHasDer),
                             uint8_t(kHasVar | kHasDer | kHasPre)}) {
          CollectLeaves(p, e, mask, &fast);
          reference = RememberedWalkLeaves(p, e, mask);
          ASSERT_EQ(fast, reference) << "nodes " << nodes << ", variables " << num_vars << ", mask " << int(mask);
        }
      }
    }
  }
}

TEST(CollectLeavesTest, OrderDoesNotFollowNodeIds) {
  // x0*p0 + x2 + der(x1) + x1, made with the leaves in two orders: the pool orders the operands
  // of + and * by node id, so the trees differ, but not the list of their leaves.
  auto leaves_with = [](bool reversed) {
    ExprPool p;
    if (reversed) {
      for (uint32_t k = 3; k-- > 0;) {
        p.Der(VarId(k));
        p.Var(VarId(k));
        p.Param(ParamId(k));
      }
    }
    const ExprId e = p.Add(p.Add(p.Add(p.Mul(p.Var(VarId(0u)), p.Param(ParamId(0u))), p.Var(VarId(2u))),
                                 p.Der(VarId(1u))),
                           p.Var(VarId(1u)));
    std::vector<std::string> names;
    for (ExprId leaf : CollectLeaves(p, e, kAllLeaves)) {
      const Node& n = p.node(leaf);
      names.push_back(std::string(n.op == Op::kDer ? "der" : n.op == Op::kParam ? "p" : "x") + std::to_string(n.a));
    }
    return names;
  };
  EXPECT_EQ(leaves_with(false), (std::vector<std::string>{"x0", "p0", "x1", "der1", "x2"}));
  EXPECT_EQ(leaves_with(true), leaves_with(false));
}

TEST(CollectLeavesTest, DeepChainIsHandedOver) {
  ExprPool p;
  ExprId e = p.Var(VarId(0u));
  for (uint32_t k = 1; k < 100000; ++k) e = p.Add(e, p.Var(VarId(k % 50)));
  std::vector<ExprId> fast, reference;
  CollectLeaves(p, e, kHasVar, &fast);
  reference = RememberedWalkLeaves(p, e, kHasVar);
  EXPECT_EQ(fast, reference);
  EXPECT_EQ(fast.size(), 50u);
}

TEST(EquationLeavesTest, AnswersAsTheSubstitutionsWalkAsEquationsChange) {
  auto pool = std::make_shared<ExprPool>();
  ExprPool& p = *pool;
  EquationSystem sys;
  sys.pool = pool;
  std::mt19937 rng(11);
  for (uint32_t k = 0; k < 200; ++k) {
    sys.equations.push_back({RandomExpression(&p, &rng, 1 + k % 25, 30), k, SystemEquation::Kind::kDynamic});
  }
  EquationLeaves leaves;
  leaves.Collect(sys);
  ASSERT_TRUE(leaves.valid());
  Substitution s(&p);
  std::uniform_int_distribution<uint32_t> var(0, 29);
  auto check = [&] {
    ASSERT_EQ(leaves.size(), sys.equations.size());
    std::vector<ExprId> reference;
    for (size_t k = 0; k < sys.equations.size(); ++k) {
      CollectLeaves(p, sys.equations[k].residual, EquationLeaves::kKinds, &reference);
      ASSERT_EQ(std::vector<ExprId>(leaves.begin(k), leaves.end(k)), reference) << "equation " << k;
      ASSERT_EQ(leaves.Touches(s, k), s.Touches(sys.equations[k].residual)) << "equation " << k;
    }
  };
  for (int step = 0; step < 5; ++step) {
    // Replace a few variables and derivatives by expressions of others (acyclic: by higher ones).
    for (int j = 0; j < 3; ++j) {
      const uint32_t v = var(rng) % 20;
      s.Set(p.Var(VarId(v)), p.Sub(p.Var(VarId(v + 10)), p.Param(ParamId(v))));
      s.Set(p.Der(VarId(v)), p.Der(VarId(v + 10)));
    }
    check();
    for (size_t k = 0; k < sys.equations.size(); ++k) {
      if (!leaves.Touches(s, k)) continue;
      sys.equations[k].residual = s.Apply(sys.equations[k].residual);
      leaves.Update(p, k, sys.equations[k].residual);
    }
    check();
    // Drop every fifth equation, then keep all but the first.
    std::vector<bool> drop(sys.equations.size(), false);
    std::vector<SystemEquation> kept;
    for (size_t k = 0; k < sys.equations.size(); ++k) {
      drop[k] = k % 5 == 4;
      if (!drop[k]) kept.push_back(sys.equations[k]);
    }
    sys.equations.swap(kept);
    leaves.Drop(drop);
    check();
    std::vector<uint32_t> keep;
    for (uint32_t k = 1; k < sys.equations.size(); ++k) keep.push_back(k);
    sys.equations.erase(sys.equations.begin());
    leaves.Keep(keep);
    check();
  }
}

}  // namespace
}  // namespace momenta
