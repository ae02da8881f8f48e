// Leaf collection (core/expr/expr_leaves.h): a small tree is walked without remembering its
// inner nodes, a large one with VisitLeaves (core/expr/expr_walk.h), which visits each node once;
// either way the leaves are then sorted by what they are (SortLeaves, core/expr/leaf_order.h), not
// left in the walk's order, which follows node ids: the passes break their ties in this order.

#include "core/expr/expr_leaves.h"

#include <algorithm>

#include "core/expr/expr_walk.h"
#include "core/expr/leaf_order.h"

namespace momenta {

namespace {

/// Past this many inner nodes, or this many leaves, CollectLeaves' walk that does not remember
/// inner nodes gives up for VisitLeaves.
constexpr size_t kWalkBudget = 256;
constexpr size_t kLeafBudget = 48;

/// VisitLeaves' leaves, in its order, for a small tree: a walk that does not remember the inner
/// nodes it has passed (a subtree shared within `e` is walked again, and its leaves, found
/// before, are skipped) costs a few instructions per node where remembering them costs a search
/// of those seen. Returns false, `out` unfinished, past the budgets.
bool CollectSmallTreeLeaves(const ExprPool& pool, ExprId e, uint8_t mask, std::vector<ExprId>* out) {
  thread_local std::vector<uint32_t> stack;
  stack.assign(1, e.value());
  size_t inner = 0;
  while (!stack.empty()) {
    const uint32_t id = stack.back();
    stack.pop_back();
    const Node& n = pool.node(ExprId(id));
    if (!(n.mask & mask)) continue;
    switch (n.op) {
      case Op::kVar:
      case Op::kDer:
      case Op::kPre:
      case Op::kParam:
        // Found again below a shared subtree walked twice: its first finding holds its place.
        if (std::find(out->begin(), out->end(), ExprId(id)) != out->end()) continue;
        if (out->size() == kLeafBudget) return false;
        out->push_back(ExprId(id));
        continue;
      default:
        break;
    }
    if (++inner > kWalkBudget) return false;
    // Children pushed as VisitLeaves pushes them (the last popped first): the same order.
    const int arity = Arity(n.op);
    if (arity >= 1) stack.push_back(n.a);
    if (arity >= 2) stack.push_back(n.b);
    if (arity >= 3) stack.push_back(n.c);
  }
  return true;
}

/// A leaf's place in LeafOrder: its variable or parameter index, then its kind, then its
/// derivative order (the node's b for der(), 0 for the other kinds).
uint64_t LeafKey(const ExprPool& pool, ExprId leaf) {
  const Node& n = pool.node(leaf);
  return static_cast<uint64_t>(n.a) << 32 | static_cast<uint64_t>(n.op) << 24 | (n.b & 0xFFFFFFu);
}

}  // namespace

void SortLeaves(const ExprPool& pool, std::vector<ExprId>* leaves) {
  std::vector<ExprId>& v = *leaves;
  if (v.size() < 2) return;
  if (v.size() <= 16) {
    // Insertion sort: an equation holds a few leaves, mostly in order already.
    for (size_t i = 1; i < v.size(); ++i) {
      const ExprId x = v[i];
      const uint64_t key = LeafKey(pool, x);
      size_t j = i;
      for (; j > 0 && LeafKey(pool, v[j - 1]) > key; --j) v[j] = v[j - 1];
      v[j] = x;
    }
    return;
  }
  std::sort(v.begin(), v.end(), [&](ExprId x, ExprId y) { return LeafKey(pool, x) < LeafKey(pool, y); });
}

void CollectLeaves(const ExprPool& pool, ExprId e, uint8_t mask, std::vector<ExprId>* out) {
  out->clear();
  if (!(pool.mask(e) & mask)) return;
  if (!CollectSmallTreeLeaves(pool, e, mask, out)) {
    out->clear();
    VisitLeaves(pool, e, mask, [&](ExprId leaf) {
      out->push_back(leaf);
      return false;
    });
  }
  SortLeaves(pool, out);
}

std::vector<ExprId> CollectLeaves(const ExprPool& pool, ExprId e, uint8_t mask) {
  std::vector<ExprId> out;
  CollectLeaves(pool, e, mask, &out);
  return out;
}

bool AllLeavesIn(const ExprPool& pool, ExprId e, uint8_t mask, const std::vector<bool>& members) {
  return !VisitLeaves(pool, e, mask, [&](ExprId leaf) { return !members[pool.node(leaf).a]; });
}

bool ContainsLeaf(const ExprPool& pool, ExprId e, ExprId leaf) {
  const uint8_t mask = MaskOfLeaf(pool.op(leaf));
  if (!(pool.mask(e) & mask)) return false;
  return VisitLeaves(pool, e, mask, [&](ExprId l) { return l == leaf; });
}

}  // namespace momenta
