// The chain rule over PostOrderWalk (core/expr/expr_walk.h), for one leaf or the time, and a
// Jacobian row's partials from one walk of the expression (PartialDerivatives).

#include "core/expr/expr_derivatives.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "core/expr/expr_leaves.h"
#include "core/expr/expr_walk.h"
#include "core/expr/leaf_order.h"

namespace momenta {

namespace {

/// The derivative of node `id` given its children's values and derivatives.
ExprId ChainRule(ExprPool& p, const Node& n, ExprId self, ExprId da, ExprId db, ExprId dc) {
  ExprId a(n.a), b(n.b);
  switch (n.op) {
    case Op::kAdd: return p.Add(da, db);
    case Op::kSub: return p.Sub(da, db);
    case Op::kNeg: return p.Neg(da);
    case Op::kMul: return p.Add(p.Mul(da, b), p.Mul(a, db));
    case Op::kDiv:
      // (a/b)' = a'/b - a b'/b^2
      return p.Sub(p.Div(da, b), p.Div(p.Mul(a, db), p.Mul(b, b)));
    case Op::kPow: {
      ExprId result = p.Zero();
      if (!p.IsConst(da, 0)) {
        // b a^(b-1) a'
        result = p.Mul(p.Mul(b, p.Pow(a, p.Sub(b, p.One()))), da);
      }
      if (!p.IsConst(db, 0)) {
        result = p.Add(result, p.Mul(p.Mul(self, p.Unary(Op::kLog, a)), db));
      }
      return result;
    }
    case Op::kSin: return p.Mul(p.Unary(Op::kCos, a), da);
    case Op::kCos: return p.Neg(p.Mul(p.Unary(Op::kSin, a), da));
    case Op::kTan: {
      ExprId c = p.Unary(Op::kCos, a);
      return p.Div(da, p.Mul(c, c));
    }
    case Op::kAsin:
      return p.Div(da, p.Unary(Op::kSqrt, p.Sub(p.One(), p.Mul(a, a))));
    case Op::kAcos:
      return p.Neg(p.Div(da, p.Unary(Op::kSqrt, p.Sub(p.One(), p.Mul(a, a)))));
    case Op::kAtan: return p.Div(da, p.Add(p.One(), p.Mul(a, a)));
    case Op::kSinh: return p.Mul(p.Unary(Op::kCosh, a), da);
    case Op::kCosh: return p.Mul(p.Unary(Op::kSinh, a), da);
    case Op::kTanh: {
      ExprId c = p.Unary(Op::kCosh, a);
      return p.Div(da, p.Mul(c, c));
    }
    case Op::kExp: return p.Mul(self, da);
    case Op::kLog: return p.Div(da, a);
    case Op::kLog10: return p.Div(da, p.Mul(a, p.Const(std::log(10.0))));
    case Op::kSqrt: return p.Div(da, p.Mul(p.Const(2.0), self));
    case Op::kAbs: return p.Mul(p.Unary(Op::kSign, a), da);
    case Op::kSign:
    case Op::kFloor: return p.Zero();
    case Op::kAtan2:
      // atan2(a, b)' = (b a' - a b') / (a^2 + b^2)
      return p.Div(p.Sub(p.Mul(b, da), p.Mul(a, db)), p.Add(p.Mul(a, a), p.Mul(b, b)));
    case Op::kMin:
      return p.If(p.Binary(Op::kLt, a, b, kNoEvent), da, db);
    case Op::kMax:
      return p.If(p.Binary(Op::kGt, a, b, kNoEvent), da, db);
    case Op::kIf:
      return p.If(a, db, dc);
    case Op::kInterp:
      // The table is data (b is its kTable leaf): only x varies.
      return p.Mul(p.Binary(Op::kInterpSlope, a, b), da);
    default:
      // Relations and logic are piecewise constant.
      return p.Zero();
  }
}

/// Generic derivative: `leaf_rule` gives the derivative of each leaf (an invalid id: none, and
/// *failed is set); `relevant_mask` says whether a subtree can have a nonzero derivative (by its
/// leaf mask), so the rest is skipped. The condition of an if has no derivative: only the
/// branches are walked.
template <class LeafRule>
ExprId Derive(ExprPool* pool, ExprId root, LeafRule leaf_rule, uint8_t relevant_mask, bool* failed) {
  ExprPool& p = *pool;
  auto settle = [&](uint32_t id, const Node& n) {
    if (!(n.mask & relevant_mask)) return p.Zero();
    if (!IsLeaf(n.op)) return ExprId();
    ExprId d = leaf_rule(n, ExprId(id));
    if (!d.valid()) {
      *failed = true;
      d = p.Zero();
    }
    return d;
  };
  auto combine = [&](uint32_t id, const Node& n, ExprId da, ExprId db, ExprId dc) {
    auto or_zero = [&](ExprId d) { return d.valid() ? d : p.Zero(); };
    return ChainRule(p, n, ExprId(id), or_zero(da), or_zero(db), or_zero(dc));
  };
  return PostOrderWalk(p, root, /*skip_if_condition=*/true, settle, combine);
}

}  // namespace

ExprId PartialDerivative(ExprPool* pool, ExprId e, ExprId leaf) {
  bool failed = false;
  uint8_t mask = MaskOfLeaf(pool->op(leaf));
  return Derive(
      pool, e,
      [&](const Node&, ExprId id) { return id == leaf ? pool->One() : pool->Zero(); }, mask,
      &failed);
}

ExprId TimeDerivative(ExprPool* pool, ExprId e) {
  bool failed = false;
  ExprId d = Derive(
      pool, e,
      [&](const Node& n, ExprId) -> ExprId {
        switch (n.op) {
          case Op::kVar: return pool->Der(VarId(n.a));
          case Op::kTime: return pool->One();
          case Op::kDer: return pool->Der(VarId(n.a), n.b + 2);
          default: return pool->Zero();
        }
      },
      kHasVar | kHasDer | kHasTime, &failed);
  return failed ? ExprId() : d;
}

/// The expression as a DAG of local nodes, numbered in the order Derive completes them (children
/// c, b, a before their parent; an if's condition not at all): Derive computes a node's
/// derivative on completion, and the nodes above one leaf complete in the same relative order
/// whatever else the walk visits, so Of() makes PartialDerivative's nodes in its order.
struct PartialDerivatives::Walk {
  NodeMemo local;                          ///< node id -> local number
  std::vector<uint32_t> ids;               ///< local number -> node id
  std::vector<std::array<int32_t, 3>> kids;  ///< local numbers of a, b, c (-1: not differentiated)
  std::vector<uint32_t> parent_start, parents;  ///< who reads each local node (CSR)
  std::vector<uint32_t> mark;              ///< == stamp: above the current leaf
  std::vector<ExprId> value;               ///< derivative of each marked node
  std::vector<uint32_t> stack, above;      ///< scratch
  uint32_t stamp = 0;
  ExprId root;
  uint8_t mask = 0;
  /// The leaves the walk reached, sorted as CollectLeaves sorts them; CollectLeaves' list unless
  /// an if-condition holds leaves of the kinds asked for (CollectLeaves visits it, this walk does
  /// not).
  std::vector<ExprId> leaves;
  bool leaves_in_order = true;
};

PartialDerivatives::PartialDerivatives(ExprPool* pool) : pool_(pool), walk_(std::make_unique<Walk>()) {}
PartialDerivatives::~PartialDerivatives() = default;

void PartialDerivatives::Reset(ExprId e, uint8_t mask) {
  const ExprPool& p = *pool_;
  Walk& w = *walk_;
  w.local.Clear();
  w.ids.clear();
  w.kids.clear();
  w.root = e;
  w.mask = mask;
  w.leaves.clear();
  w.leaves_in_order = true;
  // The local nodes in completion order (Derive's walk, restricted to subtrees with such leaves).
  auto differentiated = [&](uint32_t id) { return (p.node(ExprId(id)).mask & mask) != 0; };
  w.stack.clear();
  if (differentiated(e.value())) w.stack.push_back(e.value());
  while (!w.stack.empty()) {
    const uint32_t id = w.stack.back();
    if (w.local.Has(id)) {
      w.stack.pop_back();
      continue;
    }
    const Node& n = p.node(ExprId(id));
    const int arity = IsLeaf(n.op) ? 0 : Arity(n.op);
    const uint32_t kid_ids[3] = {n.op == Op::kIf ? 0 : n.a, n.b, n.c};
    if (n.op == Op::kIf && differentiated(n.a)) w.leaves_in_order = false;
    // The operands' local numbers (-1: not differentiated); one not numbered yet comes first.
    bool ready = true;
    std::array<int32_t, 3> kids{-1, -1, -1};
    for (int j = n.op == Op::kIf ? 1 : 0; j < arity; ++j) {
      if (!differentiated(kid_ids[j])) continue;
      const ExprId k = w.local.Find(kid_ids[j]);
      if (k.valid()) {
        kids[j] = static_cast<int32_t>(k.value());
      } else {
        w.stack.push_back(kid_ids[j]);
        ready = false;
      }
    }
    if (!ready) continue;
    w.stack.pop_back();
    w.local.Insert(id, ExprId(static_cast<uint32_t>(w.ids.size())));
    w.ids.push_back(id);
    w.kids.push_back(kids);
    // Both walks take a node's operands last first and each node once: the leaves are reached
    // in the same order.
    if (arity == 0 && (n.op == Op::kVar || n.op == Op::kDer || n.op == Op::kPre || n.op == Op::kParam)) {
      w.leaves.push_back(ExprId(id));
    }
  }
  // Readers of each node, for the walk up from a leaf.
  const size_t count = w.ids.size();
  w.parent_start.assign(count + 1, 0);
  for (const auto& k : w.kids) {
    for (int32_t c : k) {
      if (c >= 0) ++w.parent_start[c + 1];
    }
  }
  for (size_t i = 0; i < count; ++i) w.parent_start[i + 1] += w.parent_start[i];
  w.parents.resize(w.parent_start[count]);
  std::vector<uint32_t>& fill = w.stack;  // scratch: next free slot per node
  fill.assign(w.parent_start.begin(), w.parent_start.end() - 1);
  for (uint32_t q = 0; q < count; ++q) {
    for (int32_t c : w.kids[q]) {
      if (c >= 0) w.parents[fill[c]++] = q;
    }
  }
  w.mark.assign(count, 0);
  w.value.resize(count);
  w.stamp = 0;
  // The walk's leaves in CollectLeaves' order (by variable, not by the walk).
  if (w.leaves_in_order) SortLeaves(p, &w.leaves);
}

const std::vector<ExprId>& PartialDerivatives::Leaves() {
  Walk& w = *walk_;
  if (!w.leaves_in_order) {
    CollectLeaves(*pool_, w.root, w.mask, &w.leaves);
    w.leaves_in_order = true;
  }
  return w.leaves;
}

ExprId PartialDerivatives::Of(ExprId leaf) {
  ExprPool& p = *pool_;
  Walk& w = *walk_;
  const ExprId found = w.local.Find(leaf.value());
  if (!found.valid()) return p.Zero();
  // The nodes above the leaf, in completion order; every other node's derivative is 0.
  const uint32_t start = found.value();
  const uint32_t stamp = ++w.stamp;
  w.mark[start] = stamp;
  w.above.clear();
  w.stack.assign(1, start);
  while (!w.stack.empty()) {
    const uint32_t q = w.stack.back();
    w.stack.pop_back();
    for (uint32_t k = w.parent_start[q]; k < w.parent_start[q + 1]; ++k) {
      const uint32_t parent = w.parents[k];
      if (w.mark[parent] == stamp) continue;
      w.mark[parent] = stamp;
      w.above.push_back(parent);
      w.stack.push_back(parent);
    }
  }
  std::sort(w.above.begin(), w.above.end());
  // The chain rule up to the root, as Derive applies it.
  w.value[start] = p.One();
  auto derivative = [&](int32_t kid) {
    return kid >= 0 && w.mark[kid] == stamp ? w.value[kid] : p.Zero();
  };
  for (uint32_t q : w.above) {
    const Node n = p.node(ExprId(w.ids[q]));  // a copy: new nodes may move the pool
    const auto& k = w.kids[q];
    const ExprId da = derivative(k[0]), db = derivative(k[1]);
    if (n.op == Op::kDiv && p.IsConst(db, 0)) {
      // (a/b)' with b' = 0: ChainRule's a'/b - a*0/(b*b) comes to a'/b, but makes b*b, which
      // nothing reads (a node per division by a parameter in a Jacobian row).
      w.value[q] = p.Div(da, ExprId(n.b));
    } else {
      w.value[q] = ChainRule(p, n, ExprId(w.ids[q]), da, db, derivative(k[2]));
    }
  }
  const uint32_t root = static_cast<uint32_t>(w.ids.size() - 1);
  return w.mark[root] == stamp ? w.value[root] : p.Zero();
}

}  // namespace momenta
