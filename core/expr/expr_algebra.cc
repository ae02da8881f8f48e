#include "core/expr/expr_algebra.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <sstream>
#include <unordered_map>
#include <unordered_set>

#include "core/base/error.h"

namespace momenta {

namespace {
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
/// residual) then cost a few cache lines and no allocation once the scratch has grown; the
/// std::unordered_map this replaces allocated a node per entry and was a tenth of building a
/// large model's Jacobian.
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

}  // namespace

namespace {

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
    switch (n.op) {
      case Op::kVar:
      case Op::kDer:
      case Op::kPre:
      case Op::kParam:
        if (on_leaf(ExprId(id))) return true;
        continue;
      default:
        break;
    }
    int arity = Arity(n.op);
    if (arity >= 1) stack.push_back(n.a);
    if (arity >= 2) stack.push_back(n.b);
    if (arity >= 3) stack.push_back(n.c);
  }
  return false;
}

}  // namespace

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

}  // namespace

void CollectLeaves(const ExprPool& pool, ExprId e, uint8_t mask, std::vector<ExprId>* out) {
  out->clear();
  if (!(pool.mask(e) & mask)) return;
  if (CollectSmallTreeLeaves(pool, e, mask, out)) return;
  out->clear();
  VisitLeaves(pool, e, mask, [&](ExprId leaf) {
    out->push_back(leaf);
    return false;
  });
}

std::vector<ExprId> CollectLeaves(const ExprPool& pool, ExprId e, uint8_t mask) {
  std::vector<ExprId> out;
  CollectLeaves(pool, e, mask, &out);
  return out;
}

namespace {
uint8_t MaskOfLeaf(Op op) {
  switch (op) {
    case Op::kVar: return kHasVar;
    case Op::kDer: return kHasDer;
    case Op::kPre: return kHasPre;
    case Op::kParam: return kHasParam;
    default: return 0;
  }
}
}  // namespace

bool AllLeavesIn(const ExprPool& pool, ExprId e, uint8_t mask, const std::vector<bool>& members) {
  return !VisitLeaves(pool, e, mask, [&](ExprId leaf) { return !members[pool.node(leaf).a]; });
}

bool ContainsLeaf(const ExprPool& pool, ExprId e, ExprId leaf) {
  const uint8_t mask = MaskOfLeaf(pool.op(leaf));
  if (!(pool.mask(e) & mask)) return false;
  return VisitLeaves(pool, e, mask, [&](ExprId l) { return l == leaf; });
}

// ---------------------------------------------------------------------------------------------
// Substitution

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
    ExprId r;
    if (arity == 1) {
      ExprId a = result(n.a);
      r = (a.value() == n.a) ? ExprId(id) : pool.Unary(n.op, a);
    } else if (arity == 2) {
      ExprId a = result(n.a), b = result(n.b);
      r = (a.value() == n.a && b.value() == n.b) ? ExprId(id) : pool.Binary(n.op, a, b, n.flags);
    } else {
      ExprId a = result(n.a), b = result(n.b), c = result(n.c);
      r = (a.value() == n.a && b.value() == n.b && c.value() == n.c) ? ExprId(id)
                                                                      : pool.If(a, b, c);
    }
    store(id, r);
  }
  return result(root.value());
}

namespace {

/// `root` with each node for which `replacement(id)` is valid replaced by it; only subtrees whose
/// leaf mask meets `mask` are visited.
template <class Replacement>
ExprId Replace(ExprPool* pool, ExprId root, uint8_t mask, Replacement replacement) {
  ExprPool& p = *pool;
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
    const ExprId hit = replacement(id);
    const Node n = p.node(ExprId(id));
    if (hit.valid() || !(n.mask & mask) || IsLeaf(n.op)) {
      memo.Insert(id, hit.valid() ? hit : ExprId(id));
      stack.pop_back();
      continue;
    }
    int arity = Arity(n.op);
    bool ready = true;
    if (arity >= 1 && !memo.Has(n.a)) { stack.push_back(n.a); ready = false; }
    if (arity >= 2 && !memo.Has(n.b)) { stack.push_back(n.b); ready = false; }
    if (arity >= 3 && !memo.Has(n.c)) { stack.push_back(n.c); ready = false; }
    if (!ready) continue;
    stack.pop_back();
    // A node whose children came back unchanged is itself: not built again (a table lookup that
    // would find it), so rewriting one leaf of an equation costs lookups on its path only.
    const ExprId a = memo.Find(n.a);
    const ExprId b = arity >= 2 ? memo.Find(n.b) : ExprId();
    const ExprId c = arity >= 3 ? memo.Find(n.c) : ExprId();
    ExprId r;
    if (a.value() == n.a && (arity < 2 || b.value() == n.b) && (arity < 3 || c.value() == n.c)) {
      r = ExprId(id);
    } else if (arity == 1) {
      r = p.Unary(n.op, a);
    } else if (arity == 2) {
      r = p.Binary(n.op, a, b, n.flags);
    } else {
      r = p.If(a, b, c);
    }
    memo.Insert(id, r);
  }
  return memo.Find(root.value());
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

// ---------------------------------------------------------------------------------------------
// Derivatives

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
    case Op::kSign: return p.Zero();
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

/// Generic derivative: `leaf_rule` gives the derivative of each leaf; `relevant` says whether a
/// subtree can have a nonzero derivative (by its leaf mask) so the rest is skipped.
template <class LeafRule>
ExprId Derive(ExprPool* pool, ExprId root, LeafRule leaf_rule, uint8_t relevant_mask, bool* failed) {
  ExprPool& p = *pool;
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
    const Node n = p.node(ExprId(id));
    if (!(n.mask & relevant_mask)) {
      memo.Insert(id, p.Zero());
      stack.pop_back();
      continue;
    }
    if (IsLeaf(n.op)) {
      ExprId d = leaf_rule(n, ExprId(id));
      if (!d.valid()) {
        *failed = true;
        d = p.Zero();
      }
      memo.Insert(id, d);
      stack.pop_back();
      continue;
    }
    int arity = Arity(n.op);
    bool ready = true;
    // The condition of an if has no derivative: only the branches are needed.
    if (n.op != Op::kIf && arity >= 1 && !memo.Has(n.a)) { stack.push_back(n.a); ready = false; }
    if (arity >= 2 && !memo.Has(n.b)) { stack.push_back(n.b); ready = false; }
    if (arity >= 3 && !memo.Has(n.c)) { stack.push_back(n.c); ready = false; }
    if (!ready) continue;
    stack.pop_back();
    ExprId da = (n.op != Op::kIf && arity >= 1) ? memo.Find(n.a) : p.Zero();
    ExprId db = arity >= 2 ? memo.Find(n.b) : p.Zero();
    ExprId dc = arity >= 3 ? memo.Find(n.c) : p.Zero();
    memo.Insert(id, ChainRule(p, n, ExprId(id), da, db, dc));
  }
  return memo.Find(root.value());
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
  /// The leaves in completion order, which is CollectLeaves' order unless an if-condition holds
  /// leaves of the kinds asked for (CollectLeaves visits it, this walk does not).
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

// ---------------------------------------------------------------------------------------------
// Affine forms and solving

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

// ---------------------------------------------------------------------------------------------
// Printing

namespace {

int Precedence(Op op);

int Precedence(const ExprPool& pool, ExprId e) {
  // A negative number prints with a leading minus: it binds like unary minus.
  if (pool.IsConst(e) && pool.ConstValue(e) < 0) return 8;
  return Precedence(pool.op(e));
}

int Precedence(Op op) {
  switch (op) {
    case Op::kIf: return 1;
    case Op::kOr: return 2;
    case Op::kAnd: return 3;
    case Op::kNot: return 4;
    case Op::kLt: case Op::kLe: case Op::kGt: case Op::kGe: case Op::kEq: case Op::kNe:
      return 5;
    case Op::kAdd: case Op::kSub: return 6;
    case Op::kMul: case Op::kDiv: return 7;
    case Op::kNeg: return 8;
    case Op::kPow: return 9;
    default: return 10;
  }
}

std::string FormatNumber(double v) {
  std::ostringstream s;
  s.precision(15);
  s << v;
  return s.str();
}

void Print(const ExprPool& pool, ExprId e, const ExprNamer& names, int depth, std::string* out) {
  if (depth > 60 || out->size() > 4000) {
    *out += "…";
    return;
  }
  const Node& n = pool.node(e);
  auto child = [&](uint32_t c, int min_prec) {
    bool paren = Precedence(pool, ExprId(c)) < min_prec;
    if (paren) *out += "(";
    Print(pool, ExprId(c), names, depth + 1, out);
    if (paren) *out += ")";
  };
  switch (n.op) {
    case Op::kConst:
      *out += FormatNumber(n.value());
      return;
    case Op::kVar: *out += names.var ? names.var(n.a) : "x" + std::to_string(n.a); return;
    case Op::kDer:
      for (uint32_t k = 0; k <= n.b; ++k) *out += "der(";
      *out += names.var ? names.var(n.a) : "x" + std::to_string(n.a);
      for (uint32_t k = 0; k <= n.b; ++k) *out += ")";
      return;
    case Op::kPre:
      *out += "pre(" + (names.var ? names.var(n.a) : "x" + std::to_string(n.a)) + ")";
      return;
    case Op::kParam: *out += names.param ? names.param(n.a) : "p" + std::to_string(n.a); return;
    case Op::kTime: *out += "time"; return;
    case Op::kInitial: *out += "initial()"; return;
    case Op::kCj: *out += "cj"; return;
    case Op::kCond: *out += "c" + std::to_string(n.a); return;
    case Op::kTable: {
      // The table's name: its element [1,1]'s name without the subscript.
      std::string first = names.param ? names.param(n.a) : "p" + std::to_string(n.a);
      *out += first.substr(0, first.rfind('['));
      return;
    }
    case Op::kInterp:
    case Op::kInterpSlope:
      *out += n.op == Op::kInterp ? "interpolate(" : "interpolate_slope(";
      Print(pool, ExprId(n.b), names, depth + 1, out);
      *out += ", ";
      Print(pool, ExprId(n.a), names, depth + 1, out);
      *out += ", " + std::to_string(pool.node(ExprId(n.b)).TableColumn()) + ")";
      return;
    case Op::kNeg: *out += "-"; child(n.a, Precedence(Op::kNeg) + 1); return;
    case Op::kNot: *out += "not "; child(n.a, Precedence(Op::kNot)); return;
    case Op::kIf:
      *out += "if ";
      Print(pool, ExprId(n.a), names, depth + 1, out);
      *out += " then ";
      Print(pool, ExprId(n.b), names, depth + 1, out);
      *out += " else ";
      Print(pool, ExprId(n.c), names, depth + 1, out);
      return;
    default:
      break;
  }
  int arity = Arity(n.op);
  int prec = Precedence(n.op);
  if (prec == 10) {  // function call
    *out += OpName(n.op);
    *out += "(";
    Print(pool, ExprId(n.a), names, depth + 1, out);
    if (arity == 2) {
      *out += ", ";
      Print(pool, ExprId(n.b), names, depth + 1, out);
    }
    *out += ")";
    return;
  }
  bool right_assoc = n.op == Op::kPow;
  // Relations do not chain: both operands of one are parenthesised if they are relations.
  bool relation = IsRelation(n.op);
  child(n.a, right_assoc || relation ? prec + 1 : prec);
  *out += " ";
  *out += OpName(n.op);
  *out += " ";
  child(n.b, right_assoc ? prec : prec + 1);
}

}  // namespace

std::string ToString(const ExprPool& pool, ExprId e, const ExprNamer& names) {
  std::string out;
  Print(pool, e, names, 0, &out);
  return out;
}

}  // namespace momenta
