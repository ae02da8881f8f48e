#pragma once
/// The walks the algebra's files share (core/expr/ only, not a public interface): a scratch memo
/// by node id, the distinct-leaf walk, and the post-order walk that substitution and derivatives
/// are built on. Every one is iterative (explicit stack), so a 100 000-deep expression — a chain
/// of rods whose offsets add up — cannot overflow the call stack.

#include <algorithm>
#include <cstdint>
#include <unordered_set>
#include <vector>

#include "core/expr/expr.h"

namespace momenta {

/// Empties a scratch hash container; one that grew large is replaced, since clear() costs time
/// in proportion to its bucket count and would tax every later small call.
template <class Container>
void ResetScratch(Container* c) {
  if (c->bucket_count() > 1024) {
    Container().swap(*c);
  } else if (!c->empty()) {
    c->clear();
  }
}

/// Results by node id for one traversal of one expression: open addressing in a power-of-two
/// array that grows with the expression. The small expressions of most calls (an equation, a
/// residual) then cost a few cache lines and no allocation once the scratch has grown; a
/// std::unordered_map allocates a node per entry, a tenth of building a large model's Jacobian.
class NodeMemo {
 public:
  /// Forgets every entry; an array grown large by one big expression is given back.
  void Clear() {
    if (slots_.size() > 4096 || slots_.empty()) {
      slots_.assign(64, kEmpty);
    } else if (used_ > 0) {
      std::fill(slots_.begin(), slots_.end(), kEmpty);
    }
    used_ = 0;
  }
  /// The entry of `id`, or an invalid id.
  ExprId Find(uint32_t id) const {
    const size_t mask = slots_.size() - 1;
    for (size_t k = Slot(id, mask);; k = (k + 1) & mask) {
      const uint64_t e = slots_[k];
      if (e == kEmpty) return ExprId();
      if (static_cast<uint32_t>(e >> 32) == id) return ExprId(static_cast<uint32_t>(e));
    }
  }
  bool Has(uint32_t id) const { return Find(id).valid(); }
  /// Sets the entry of an id that has none.
  void Insert(uint32_t id, ExprId value) {
    if ((used_ + 1) * 2 > slots_.size()) Grow();
    Place(&slots_, (static_cast<uint64_t>(id) << 32) | value.value());
    ++used_;
  }

 private:
  static constexpr uint64_t kEmpty = ~0ull;
  static size_t Slot(uint32_t id, size_t mask) { return (static_cast<size_t>(id) * 0x9E3779B97F4A7C15ull >> 17) & mask; }
  static void Place(std::vector<uint64_t>* slots, uint64_t entry) {
    const size_t mask = slots->size() - 1;
    size_t k = Slot(static_cast<uint32_t>(entry >> 32), mask);
    while ((*slots)[k] != kEmpty) k = (k + 1) & mask;
    (*slots)[k] = entry;
  }
  void Grow() {
    std::vector<uint64_t> bigger(slots_.size() * 2, kEmpty);
    for (uint64_t e : slots_) {
      if (e != kEmpty) Place(&bigger, e);
    }
    slots_.swap(bigger);
  }

  std::vector<uint64_t> slots_;
  size_t used_ = 0;
};

/// The LeafMask bit of a leaf kind that VisitLeaves reports (kVar, kDer, kPre, kParam); 0 for
/// the others.
inline uint8_t MaskOfLeaf(Op op) {
  switch (op) {
    case Op::kVar: return kHasVar;
    case Op::kDer: return kHasDer;
    case Op::kPre: return kHasPre;
    case Op::kParam: return kHasParam;
    default: return 0;
  }
}

/// Calls `on_leaf(id)` once for each distinct leaf (kVar, kDer, kPre, kParam) below `e` in a
/// subtree whose leaf mask meets `mask`, until it returns true; returns whether one did.
template <class OnLeaf>
bool VisitLeaves(const ExprPool& pool, ExprId e, uint8_t mask, OnLeaf on_leaf) {
  // Most expressions are small: a linear scan of what was seen beats a hash set until it grows.
  // Scratch reused across calls (these run once per equation in every pass).
  thread_local std::vector<uint32_t> seen_small, stack;
  thread_local std::unordered_set<uint32_t> seen_large;
  seen_small.clear();
  ResetScratch(&seen_large);
  stack.clear();
  auto first_visit = [&](uint32_t id) {
    if (seen_large.empty()) {
      for (uint32_t s : seen_small) {
        if (s == id) return false;
      }
      seen_small.push_back(id);
      if (seen_small.size() > 48) seen_large.insert(seen_small.begin(), seen_small.end());
      return true;
    }
    return seen_large.insert(id).second;
  };
  stack.push_back(e.value());
  while (!stack.empty()) {
    uint32_t id = stack.back();
    stack.pop_back();
    const Node& n = pool.node(ExprId(id));
    if (!(n.mask & mask)) continue;
    if (!first_visit(id)) continue;
    if (MaskOfLeaf(n.op) != 0) {
      if (on_leaf(ExprId(id))) return true;
      continue;
    }
    int arity = Arity(n.op);
    if (arity >= 1) stack.push_back(n.a);
    if (arity >= 2) stack.push_back(n.b);
    if (arity >= 3) stack.push_back(n.c);
  }
  return false;
}

/// A walk that computes one result per node below `root`, children before their parent, each
/// node once (a subtree shared within `root` is done once), and returns the root's. It is the
/// skeleton of substitution (ReplaceNodes) and of derivatives (Derive).
///
/// `settle(id, node)` gives the result of a node that needs none of its operands' (a leaf, a
/// subtree to keep as it is or to skip), or an invalid id to have the operands done first;
/// `combine(id, node, a, b, c)` then makes the node's result from its operands' (invalid for an
/// operand the node lacks or the walk skipped). With `skip_if_condition`, an if-expression's
/// condition is not walked. `node` is a copy: the callbacks may add nodes, which moves the pool.
template <class Settle, class Combine>
ExprId PostOrderWalk(const ExprPool& pool, ExprId root, bool skip_if_condition, Settle settle,
                     Combine combine) {
  thread_local NodeMemo memo;
  thread_local std::vector<uint32_t> stack;
  memo.Clear();
  stack.assign(1, root.value());
  while (!stack.empty()) {
    uint32_t id = stack.back();
    if (memo.Has(id)) {
      stack.pop_back();
      continue;
    }
    const Node n = pool.node(ExprId(id));
    if (const ExprId settled = settle(id, n); settled.valid()) {
      memo.Insert(id, settled);
      stack.pop_back();
      continue;
    }
    // The operands not done yet go first; the node is finished when none is left.
    const int arity = Arity(n.op);
    const bool walk_a = arity >= 1 && !(skip_if_condition && n.op == Op::kIf);
    bool ready = true;
    if (walk_a && !memo.Has(n.a)) { stack.push_back(n.a); ready = false; }
    if (arity >= 2 && !memo.Has(n.b)) { stack.push_back(n.b); ready = false; }
    if (arity >= 3 && !memo.Has(n.c)) { stack.push_back(n.c); ready = false; }
    if (!ready) continue;
    stack.pop_back();
    const ExprId a = walk_a ? memo.Find(n.a) : ExprId();
    const ExprId b = arity >= 2 ? memo.Find(n.b) : ExprId();
    const ExprId c = arity >= 3 ? memo.Find(n.c) : ExprId();
    memo.Insert(id, combine(id, n, a, b, c));
  }
  return memo.Find(root.value());
}

/// Node `id` (`n`, a copy) with its operands' results `a`, `b`, `c` (those it has): the node
/// itself when they came back unchanged — not built again, a table lookup that would find it, so
/// rewriting one leaf of an equation costs lookups on its path only — else the node built anew.
inline ExprId WithOperands(ExprPool* pool, uint32_t id, const Node& n, ExprId a, ExprId b,
                           ExprId c) {
  const int arity = Arity(n.op);
  if (a.value() == n.a && (arity < 2 || b.value() == n.b) && (arity < 3 || c.value() == n.c)) {
    return ExprId(id);
  }
  if (arity == 1) return pool->Unary(n.op, a);
  if (arity == 2) return pool->Binary(n.op, a, b, n.flags);
  return pool->If(a, b, c);
}

}  // namespace momenta
