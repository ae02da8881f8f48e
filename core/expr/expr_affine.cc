// Affine decomposition and solving for a leaf (core/expr/expr_affine.h): explicit-stack walks,
// so a flow sum over a 100 000-member connection set decomposes without deep recursion.

#include "core/expr/expr_affine.h"

#include <algorithm>
#include <cmath>
#include <unordered_map>

#include "core/expr/expr_derivatives.h"
#include "core/expr/expr_leaves.h"
#include "core/expr/expr_substitution.h"
#include "core/expr/expr_walk.h"

namespace momenta {

namespace {

/// Walks sums, differences, negations and scalings by numbers with an explicit stack, so a flow
/// sum over a 100 000-member connection set is no problem; stops at the first non-affine node or
/// when there are more than `max_terms` distinct leaves.
bool AffineWalk(ExprPool* pool, ExprId root, size_t max_terms, AffineForm* out) {
  ExprPool& p = *pool;
  thread_local std::vector<std::pair<ExprId, double>> stack;
  stack.assign(1, {root, 1.0});
  std::unordered_map<uint32_t, size_t> index;  // leaf -> term, once there are many terms
  while (!stack.empty()) {
    auto [e, scale] = stack.back();
    stack.pop_back();
    if (p.IsParamOnly(e)) {
      out->offset = p.Add(out->offset, scale == 1.0 ? e : p.Mul(p.Const(scale), e));
      continue;
    }
    const Node& n = p.node(e);
    switch (n.op) {
      case Op::kVar:
      case Op::kDer: {
        // A linear scan while the form is short (the common case), a map beyond that.
        bool found = false;
        if (out->terms.size() <= 8) {
          for (auto& t : out->terms) {
            if (t.first == e) {
              t.second += scale;
              found = true;
              break;
            }
          }
        } else {
          if (index.empty()) {
            for (size_t k = 0; k < out->terms.size(); ++k) index.emplace(out->terms[k].first.value(), k);
          }
          auto it = index.find(e.value());
          if (it != index.end()) {
            out->terms[it->second].second += scale;
            found = true;
          }
        }
        if (!found) {
          if (out->terms.size() >= max_terms) return false;
          if (!index.empty()) index.emplace(e.value(), out->terms.size());
          out->terms.emplace_back(e, scale);
        }
        break;
      }
      case Op::kAdd:
        stack.push_back({ExprId(n.b), scale});
        stack.push_back({ExprId(n.a), scale});
        break;
      case Op::kSub:
        stack.push_back({ExprId(n.b), -scale});
        stack.push_back({ExprId(n.a), scale});
        break;
      case Op::kNeg:
        stack.push_back({ExprId(n.a), -scale});
        break;
      case Op::kMul:
        if (p.IsConst(ExprId(n.a))) {
          stack.push_back({ExprId(n.b), scale * p.ConstValue(ExprId(n.a))});
        } else if (p.IsConst(ExprId(n.b))) {
          stack.push_back({ExprId(n.a), scale * p.ConstValue(ExprId(n.b))});
        } else {
          return false;
        }
        break;
      case Op::kDiv:
        if (p.IsConst(ExprId(n.b)) && p.ConstValue(ExprId(n.b)) != 0) {
          stack.push_back({ExprId(n.a), scale / p.ConstValue(ExprId(n.b))});
        } else {
          return false;
        }
        break;
      default:
        return false;
    }
  }
  return true;
}

}  // namespace

bool DecomposeAffine(ExprPool* pool, ExprId e, size_t max_terms, AffineForm* out) {
  out->terms.clear();
  out->offset = pool->Zero();
  if (!AffineWalk(pool, e, max_terms, out)) return false;
  // Terms that cancelled (x - x) are dropped.
  out->terms.erase(std::remove_if(out->terms.begin(), out->terms.end(),
                                  [](const auto& t) { return t.second == 0.0; }),
                   out->terms.end());
  return true;
}

namespace {
/// True when `e` is affine in `leaf`: it occurs only through sums, differences, negation, products
/// with factors free of it, quotients by such factors, and if-branches (never in a condition,
/// relation, sign, abs, min or max, whose derivative vanishes without the function being linear).
bool IsAffineIn(const ExprPool& p, ExprId e, ExprId leaf, int depth = 0) {
  if (e == leaf) return true;
  if (!ContainsLeaf(p, e, leaf)) return true;
  if (depth > 200) return false;
  const Node& n = p.node(e);
  switch (n.op) {
    case Op::kAdd:
    case Op::kSub:
      return IsAffineIn(p, ExprId(n.a), leaf, depth + 1) && IsAffineIn(p, ExprId(n.b), leaf, depth + 1);
    case Op::kNeg:
      return IsAffineIn(p, ExprId(n.a), leaf, depth + 1);
    case Op::kMul:
      if (!ContainsLeaf(p, ExprId(n.a), leaf)) return IsAffineIn(p, ExprId(n.b), leaf, depth + 1);
      if (!ContainsLeaf(p, ExprId(n.b), leaf)) return IsAffineIn(p, ExprId(n.a), leaf, depth + 1);
      return false;
    case Op::kDiv:
      return !ContainsLeaf(p, ExprId(n.b), leaf) && IsAffineIn(p, ExprId(n.a), leaf, depth + 1);
    case Op::kIf:
      return !ContainsLeaf(p, ExprId(n.a), leaf) && IsAffineIn(p, ExprId(n.b), leaf, depth + 1) &&
             IsAffineIn(p, ExprId(n.c), leaf, depth + 1);
    default:
      return false;
  }
}

/// True when `e` does not hold `leaf` and its derivative by `leaf`, zero, would come out of
/// PartialDerivative without a node added to the pool: the subtrees that hold leaves of its kind
/// are sums, differences, negations and products (with finite constants) of leaves. (The chain
/// rule of a quotient or a function builds its factors before the zero derivative of the
/// argument multiplies them away.)
bool FreeOfLeafDerivativeBuildsNothing(const ExprPool& p, ExprId e, ExprId leaf) {
  const uint8_t mask = MaskOfLeaf(p.op(leaf));
  thread_local NodeMemo seen;
  thread_local std::vector<uint32_t> stack;
  seen.Clear();
  stack.assign(1, e.value());
  auto finite_factor = [&](uint32_t id) {
    return !p.IsConst(ExprId(id)) || std::isfinite(p.ConstValue(ExprId(id)));
  };
  while (!stack.empty()) {
    const uint32_t id = stack.back();
    stack.pop_back();
    const Node& n = p.node(ExprId(id));
    if (!(n.mask & mask) || seen.Has(id)) continue;
    seen.Insert(id, ExprId(id));
    if (id == leaf.value()) return false;
    switch (n.op) {
      case Op::kVar:
      case Op::kDer:
      case Op::kPre:
      case Op::kParam:
        continue;  // another leaf
      case Op::kMul:
        if (!finite_factor(n.a) || !finite_factor(n.b)) return false;
        [[fallthrough]];
      case Op::kAdd:
      case Op::kSub:
        stack.push_back(n.a);
        stack.push_back(n.b);
        continue;
      case Op::kNeg:
        stack.push_back(n.a);
        continue;
      default:
        return false;
    }
  }
  return true;
}

}  // namespace

ExprId SolveFor(ExprPool* pool, ExprId residual, ExprId leaf, bool param_coefficient_ok,
                ExprId* coefficient) {
  ExprPool& p = *pool;
  // The explicit forms leaf - rest and rest - leaf (most equations the passes solve), with rest
  // free of the leaf: the coefficient is 1 or -1, and the steps below would build exactly the
  // nodes built here, after three more walks of rest.
  if (const Node& r = p.node(residual); r.op == Op::kSub && (r.a == leaf.value()) != (r.b == leaf.value())) {
    const bool leaf_first = r.a == leaf.value();
    const ExprId rest(leaf_first ? r.b : r.a);
    if (FreeOfLeafDerivativeBuildsNothing(p, rest, leaf)) {
      if (leaf_first) {  // a = 1, b = 0 - rest
        if (coefficient) *coefficient = p.One();
        return p.Neg(p.Sub(p.Zero(), rest));
      }
      if (coefficient) *coefficient = p.Const(-1.0);  // a = -1, b = rest - 0
      return p.Sub(rest, p.Zero());
    }
  }
  if (!IsAffineIn(p, residual, leaf)) return ExprId();
  ExprId a = PartialDerivative(pool, residual, leaf);
  if (p.IsConst(a)) {
    if (p.ConstValue(a) == 0.0 || !std::isfinite(p.ConstValue(a))) return ExprId();
  } else if (!(param_coefficient_ok && p.IsParamOnly(a))) {
    return ExprId();
  }
  if (ContainsLeaf(p, a, leaf)) return ExprId();
  ExprId b = ReplaceLeaf(pool, residual, leaf, p.Zero());
  if (coefficient) *coefficient = a;
  // a*leaf + b = 0  =>  leaf = -b/a
  if (p.IsConst(a, 1.0)) return p.Neg(b);
  if (p.IsConst(a, -1.0)) return b;
  return p.Neg(p.Div(b, a));
}

}  // namespace momenta
