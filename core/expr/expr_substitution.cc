// Substitution (a memo by node id that lives across calls, for the passes' accumulated
// eliminations) and one-off replacement over PostOrderWalk (core/expr/expr_walk.h).

#include "core/expr/expr_substitution.h"

#include "core/expr/expr_walk.h"

namespace momenta {

const std::vector<ExprId>* Substitution::Table(const Node& n) const {
  switch (n.op) {
    case Op::kVar: return &by_var_;
    case Op::kDer: return n.b == 0 ? &by_der_ : nullptr;  // b: the order less one
    case Op::kPre: return &by_pre_;
    case Op::kParam: return &by_param_;
    default: return nullptr;
  }
}

ExprId Substitution::Replacement(uint32_t id, const Node& n) const {
  const std::vector<ExprId>* table = Table(n);
  if (table != nullptr) return n.a < table->size() ? (*table)[n.a] : ExprId();
  if (other_.empty()) return ExprId();
  auto it = other_.find(id);
  return it == other_.end() ? ExprId() : it->second;
}

void Substitution::Set(ExprId leaf, ExprId replacement) {
  const Node n = pool_->node(leaf);
  std::vector<ExprId>* table = const_cast<std::vector<ExprId>*>(Table(n));
  ExprId* slot;
  if (table == nullptr) {
    slot = &other_[leaf.value()];
  } else {
    if (table->size() <= n.a) table->resize(n.a + 1);
    slot = &(*table)[n.a];
  }
  if (!slot->valid()) ++num_entries_;
  *slot = replacement;
  // A leaf's mask is its kind; a constant has none, and then no subtree can be skipped.
  const uint8_t kind = pool_->mask(leaf);
  mapped_kinds_ |= kind != 0 ? kind : 0xff;
  ++gen_;  // invalidates the memo
}

bool Substitution::Touches(ExprId e) const {
  // Only leaves of the four kinds VisitLeaves reports are ever mapped (the passes map variables,
  // derivatives and pre-values); any other mapped kind makes the answer a conservative yes.
  if (mapped_kinds_ & ~(kHasVar | kHasDer | kHasPre | kHasParam)) return true;
  if (num_entries_ == 0) return false;
  return VisitLeaves(*pool_, e, mapped_kinds_, [&](ExprId leaf) { return Has(leaf); });
}

void Substitution::ReleaseMemo() {
  std::vector<ExprId>().swap(memo_);
  std::vector<uint32_t>().swap(memo_gen_);
}

bool Substitution::Has(ExprId leaf) const {
  return Replacement(leaf.value(), pool_->node(leaf)).valid();
}

ExprId Substitution::Apply(ExprId root) {
  ExprPool& pool = *pool_;
  // A subtree without a leaf of a mapped kind is unchanged: it is neither walked nor memoised.
  const bool by_kind = mapped_kinds_ != 0xff;  // false once a constant is mapped
  if (by_kind && !(pool.mask(root) & mapped_kinds_)) return root;
  thread_local std::vector<uint32_t> stack;
  stack.assign(1, root.value());
  auto unchanged = [&](uint32_t id) { return by_kind && !(pool.node(ExprId(id)).mask & mapped_kinds_); };
  auto done = [&](uint32_t id) {
    return (id < memo_gen_.size() && memo_gen_[id] == gen_) || unchanged(id);
  };
  auto result = [&](uint32_t id) -> ExprId { return unchanged(id) ? ExprId(id) : memo_[id]; };
  auto store = [&](uint32_t id, ExprId r) {
    if (memo_.size() <= id) {
      memo_.resize(id + 1 + id / 2);
      memo_gen_.resize(memo_.size(), 0);
    }
    memo_[id] = r;
    memo_gen_[id] = gen_;
  };
  while (!stack.empty()) {
    uint32_t id = stack.back();
    if (done(id)) {
      stack.pop_back();
      continue;
    }
    const Node n = pool.node(ExprId(id));
    if (IsLeaf(n.op)) {
      if (const ExprId mapped = Replacement(id, n); mapped.valid()) {
        uint32_t rep = mapped.value();
        if (rep == id) {
          store(id, ExprId(id));
          stack.pop_back();
        } else if (done(rep)) {
          store(id, result(rep));
          stack.pop_back();
        } else {
          stack.push_back(rep);
        }
      } else {
        store(id, ExprId(id));
        stack.pop_back();
      }
      continue;
    }
    // Children without a mapped kind of leaf count as done (unchanged).
    int arity = Arity(n.op);
    bool ready = true;
    if (arity >= 1 && !done(n.a)) { stack.push_back(n.a); ready = false; }
    if (arity >= 2 && !done(n.b)) { stack.push_back(n.b); ready = false; }
    if (arity >= 3 && !done(n.c)) { stack.push_back(n.c); ready = false; }
    if (!ready) continue;
    stack.pop_back();
    const ExprId a = result(n.a);
    const ExprId b = arity >= 2 ? result(n.b) : ExprId();
    const ExprId c = arity >= 3 ? result(n.c) : ExprId();
    store(id, WithOperands(pool_, id, n, a, b, c));
  }
  return result(root.value());
}

namespace {

/// `root` with each node for which `replacement(id)` is valid replaced by it; only subtrees whose
/// leaf mask meets `mask` are visited.
template <class Replacement>
ExprId Replace(ExprPool* pool, ExprId root, uint8_t mask, Replacement replacement) {
  auto settle = [&](uint32_t id, const Node& n) {
    const ExprId hit = replacement(id);
    if (hit.valid()) return hit;
    return !(n.mask & mask) || IsLeaf(n.op) ? ExprId(id) : ExprId();
  };
  auto combine = [&](uint32_t id, const Node& n, ExprId a, ExprId b, ExprId c) {
    return WithOperands(pool, id, n, a, b, c);
  };
  return PostOrderWalk(*pool, root, /*skip_if_condition=*/false, settle, combine);
}

}  // namespace

ExprId ReplaceNodes(ExprPool* pool, ExprId root, const std::unordered_map<uint32_t, ExprId>& map,
                    uint8_t mask) {
  return Replace(pool, root, mask, [&](uint32_t id) {
    auto hit = map.find(id);
    return hit != map.end() ? hit->second : ExprId();
  });
}

ExprId ReplaceLeaf(ExprPool* pool, ExprId root, ExprId leaf, ExprId value) {
  // One leaf: compared directly, no map to build per call (solving an equation calls this).
  return Replace(pool, root, MaskOfLeaf(pool->op(leaf)),
                 [&](uint32_t id) { return id == leaf.value() ? value : ExprId(); });
}

}  // namespace momenta
