#include "core/expr/expr.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <unordered_map>

#include "core/base/error.h"
#include "core/expr/expr_testing.h"

namespace momenta {

namespace {

constexpr uint64_t kEmptySlot = ~0ull;

uint64_t HashNode(const Node& n) {
  uint64_t h = static_cast<uint64_t>(n.op) * 0x9E3779B97F4A7C15ull;
  h ^= (static_cast<uint64_t>(n.a) + 0x632BE59BD9B4E019ull + (h << 6) + (h >> 2));
  h ^= (static_cast<uint64_t>(n.b) * 0xC2B2AE3D27D4EB4Full + (h << 6) + (h >> 2));
  h ^= (static_cast<uint64_t>(n.c) * 0x165667B19E3779F9ull + (h << 6) + (h >> 2));
  h ^= n.flags + (h << 6) + (h >> 2);
  h ^= h >> 33;
  h *= 0xff51afd7ed558ccdull;
  h ^= h >> 33;
  return h;
}

/// The 32-bit tag stored in the table; also the slot index source.
uint32_t Tag(const Node& n) {
  uint64_t h = HashNode(n);
  return static_cast<uint32_t>(h ^ (h >> 32));
}

/// The slot a tag's probe starts at: the tag scaled to the table's size (any size, not only
/// powers of two, so the table can grow by half at three quarters full: 11 to 16 bytes per node,
/// where doubling at half full took 16 to 32).
size_t HomeSlot(uint32_t tag, size_t size) { return static_cast<size_t>((static_cast<uint64_t>(tag) * size) >> 32); }
size_t NextSlot(size_t slot, size_t size) { return slot + 1 == size ? 0 : slot + 1; }
/// Whether `entries` would fill `slots` past three quarters.
bool TooFull(size_t entries, size_t slots) { return entries * 4 > slots * 3; }

bool SameNode(const Node& x, const Node& y) {
  return x.op == y.op && x.a == y.a && x.b == y.b && x.c == y.c && x.flags == y.flags;
}

bool IsCommutative(Op op) {
  return op == Op::kAdd || op == Op::kMul || op == Op::kMin || op == Op::kMax ||
         op == Op::kAnd || op == Op::kOr || op == Op::kEq || op == Op::kNe;
}

/// Which of ExprPool::leaf_index_ holds the leaf `n`, or -1 when it is found by hash.
int LeafIndexKind(const Node& n) {
  switch (n.op) {
    case Op::kVar: return 0;
    case Op::kParam: return 1;
    case Op::kPre: return 2;
    case Op::kDer: return n.b == 0 ? 3 : -1;
    default: return -1;
  }
}

}  // namespace

ExprPool::ExprPool() {
  table_.assign(256, kEmptySlot);
  young_.assign(kFirstYoungSlots, kEmptySlot);
  Node z;
  z.op = Op::kConst;
  zero_ = Intern(z);
  one_ = Const(1.0);
  minus_one_ = Const(-1.0);
  time_ = Leaf(Op::kTime, 0);
  if (pool_made_for_testing != nullptr) pool_made_for_testing(this);
}

void (*pool_made_for_testing)(ExprPool* pool) = nullptr;

void ExprPool::Reserve(size_t nodes) {
  if (TooFull(nodes, table_.size())) Rehash(nodes / 3 * 4 + 1024);
}

void ExprPool::Rehash(size_t slots) {
  std::vector<uint64_t, HugePageAllocator<uint64_t>> old;
  old.swap(table_);
  table_.assign(slots, kEmptySlot);
  const size_t size = table_.size();
  for (uint64_t entry : old) {
    if (entry == kEmptySlot) continue;
    size_t slot = HomeSlot(static_cast<uint32_t>(entry >> 32), size);
    while (table_[slot] != kEmptySlot) slot = NextSlot(slot, size);
    table_[slot] = entry;
  }
}

size_t ExprPool::Probe(const uint64_t* table, size_t size, uint32_t tag, const Node& n, ExprId* found) const {
  size_t slot = HomeSlot(tag, size);
  while (table[slot] != kEmptySlot) {
    const uint64_t entry = table[slot];
    if (static_cast<uint32_t>(entry >> 32) == tag && SameNode(nodes_[static_cast<uint32_t>(entry)], n)) {
      *found = ExprId(static_cast<uint32_t>(entry));
      return slot;
    }
    slot = NextSlot(slot, size);
  }
  return slot;
}

bool ExprPool::ChildrenAreYoung(const Node& n) const {
  const int arity = Arity(n.op);
  if (arity == 0) return false;
  uint32_t newest = n.a;
  if (arity >= 2) newest = std::max(newest, n.b);
  if (arity >= 3) newest = std::max(newest, n.c);
  return newest >= young_first_;
}

void ExprPool::Mature() {
  size_t slots = table_.size();
  while (TooFull(table_used_ + young_used_, slots)) slots = slots / 2 * 3;
  if (slots != table_.size()) Rehash(slots);
  // Gather the entries, then insert them with the home slot of an entry kAhead places on
  // prefetched: the inserts' cache misses overlap instead of following one another.
  size_t count = 0;
  for (uint64_t entry : young_) {
    if (entry != kEmptySlot) young_[count++] = entry;
  }
  constexpr size_t kAhead = 16;
  const size_t size = table_.size();
  for (size_t k = 0; k < count; ++k) {
    if (k + kAhead < count) __builtin_prefetch(&table_[HomeSlot(static_cast<uint32_t>(young_[k + kAhead] >> 32), size)], 1);
    size_t slot = HomeSlot(static_cast<uint32_t>(young_[k] >> 32), size);
    while (table_[slot] != kEmptySlot) slot = NextSlot(slot, size);
    table_[slot] = young_[k];
  }
  table_used_ += young_used_;
  // A pool that keeps growing gets the full nursery; a small one (a template's scratch pool, a
  // small model's) never fills more than its first.
  young_.assign(std::min(young_.size() * 4, kYoungSlots), kEmptySlot);
  young_used_ = 0;
  young_first_ = static_cast<uint32_t>(nodes_.size());
}

ExprId ExprPool::Intern(const Node& n) {
  uint32_t* indexed = nullptr;
  size_t young_slot = 0;
  uint32_t tag = 0;
  if (const int kind = LeafIndexKind(n); kind >= 0) {
    std::vector<uint32_t>& index = leaf_index_[kind];
    if (n.a >= index.size()) index.resize(static_cast<size_t>(n.a) + 1, 0);
    if (index[n.a] != 0) return ExprId(index[n.a]);
    indexed = &index[n.a];
  } else {
    // A node equal to `n` is younger than each of its children: when one of them is in the
    // nursery, so is it, and the main table (a cache miss) need not be probed.
    tag = Tag(n);
    ExprId found;
    young_slot = Probe(young_.data(), young_.size(), tag, n, &found);
    if (found.valid()) return found;
    if (!ChildrenAreYoung(n)) {
      Probe(table_.data(), table_.size(), tag, n, &found);
      if (found.valid()) return found;
    }
  }
  Node stored = n;
  // The leaf-kind mask of the subtree.
  switch (n.op) {
    case Op::kVar: stored.mask = kHasVar; break;
    case Op::kDer: stored.mask = kHasDer; break;
    case Op::kPre: stored.mask = kHasPre; break;
    case Op::kParam: stored.mask = kHasParam; break;
    case Op::kTable: stored.mask = kHasParam; break;
    case Op::kTime: stored.mask = kHasTime; break;
    case Op::kInitial: stored.mask = kHasInitial; break;
    case Op::kCj: stored.mask = kHasTime; break;
    case Op::kCond: stored.mask = kHasCond; break;
    case Op::kConst: stored.mask = 0; break;
    default: {
      int arity = Arity(n.op);
      uint8_t m = 0;
      if (arity >= 1) m |= nodes_[n.a].mask;
      if (arity >= 2) m |= nodes_[n.b].mask;
      if (arity >= 3) m |= nodes_[n.c].mask;
      if (IsRelation(n.op)) m |= kHasRelation;
      stored.mask = m;
      stored.traits = Traits(n);
    }
  }
  uint32_t id = static_cast<uint32_t>(nodes_.size());
  nodes_.push_back(stored);
  if (indexed != nullptr) {
    *indexed = id;
    return ExprId(id);
  }
  young_[young_slot] = (static_cast<uint64_t>(tag) << 32) | id;
  if (++young_used_ * 2 >= young_.size()) Mature();
  return ExprId(id);
}

uint8_t ExprPool::Traits(const Node& n) const {
  const int arity = Arity(n.op);
  uint8_t traits = 0;
  if (arity >= 1) traits |= nodes_[n.a].traits;
  if (arity >= 2) traits |= nodes_[n.b].traits;
  if (arity >= 3) traits |= nodes_[n.c].traits;
  // An operation on constants only is here unfolded because its value is not finite.
  const bool on_constants = (arity == 1 && nodes_[n.a].op == Op::kConst) ||
                            (arity == 2 && nodes_[n.a].op == Op::kConst && nodes_[n.b].op == Op::kConst);
  // A division by the constant zero: x/0 of anything.
  if (n.op == Op::kDiv && nodes_[n.b].op == Op::kConst && nodes_[n.b].value() == 0.0) traits |= kSingular;
  if (n.op == Op::kIf) traits |= kHasIf;
  if (on_constants) {
    const double v = arity == 1 ? ApplyUnary(n.op, nodes_[n.a].value())
                                : ApplyBinary(n.op, nodes_[n.a].value(), nodes_[n.b].value());
    if (!std::isfinite(v)) traits |= kSingular;
  }
  return traits;
}

ExprId ExprPool::FindLeaf(Op op, uint32_t payload) const {
  Node n;
  n.op = op;
  n.a = payload;
  if (const int kind = LeafIndexKind(n); kind >= 0) {
    const std::vector<uint32_t>& index = leaf_index_[kind];
    return payload < index.size() && index[payload] != 0 ? ExprId(index[payload]) : ExprId();
  }
  const uint32_t tag = Tag(n);
  ExprId found;
  Probe(young_.data(), young_.size(), tag, n, &found);
  if (!found.valid()) Probe(table_.data(), table_.size(), tag, n, &found);
  return found;
}

ExprId ExprPool::Der(VarId v, uint32_t order) {
  MOMENTA_CHECK_MSG(order >= 1, "a derivative has order 1 or more");
  Node n;
  n.op = Op::kDer;
  n.a = v.value();
  n.b = order - 1;
  return Intern(n);
}

ExprId ExprPool::Leaf(Op op, uint32_t payload) {
  Node n;
  n.op = op;
  n.a = payload;
  return Intern(n);
}

ExprId ExprPool::Table(ParamId first, uint32_t rows, uint32_t cols, uint32_t column) {
  MOMENTA_CHECK_MSG(rows >= 1 && column >= 1 && column <= cols && cols <= kMaxTableColumns,
                    "a table column lies in the table");
  Node n;
  n.op = Op::kTable;
  n.a = first.value();
  n.b = rows;
  n.c = cols | column << 16;
  return Intern(n);
}

ExprId ExprPool::Const(double v) {
  // The constants every pass makes most: no table lookup.
  if (v == 0.0) return zero_;
  if (v == 1.0 && one_.valid()) return one_;
  if (v == -1.0 && minus_one_.valid()) return minus_one_;
  Node n;
  n.op = Op::kConst;
  n.set_value((v == 0.0) ? 0.0 : v);  // one zero, not two
  return Intern(n);
}

bool ExprPool::IsTruthValued(ExprId id) const {
  const Node& n = node(id);
  if (n.op == Op::kConst) return n.value() == 0.0 || n.value() == 1.0;
  return IsBooleanOp(n.op);
}

bool ExprPool::IsConst(ExprId id, double v) const {
  const Node& n = node(id);
  return n.op == Op::kConst && n.value() == v;
}

ExprId ExprPool::Add(ExprId a, ExprId b) { return Binary(Op::kAdd, a, b); }
ExprId ExprPool::Sub(ExprId a, ExprId b) { return Binary(Op::kSub, a, b); }
ExprId ExprPool::Mul(ExprId a, ExprId b) { return Binary(Op::kMul, a, b); }
ExprId ExprPool::Div(ExprId a, ExprId b) { return Binary(Op::kDiv, a, b); }
ExprId ExprPool::Pow(ExprId a, ExprId b) { return Binary(Op::kPow, a, b); }

ExprId ExprPool::Neg(ExprId a) {
  const Node& n = node(a);
  if (n.op == Op::kConst) return Const(-n.value());
  if (n.op == Op::kNeg) return ExprId(n.a);
  if (n.op == Op::kSub) return Sub(ExprId(n.b), ExprId(n.a));
  Node m;
  m.op = Op::kNeg;
  m.a = a.value();
  return Intern(m);
}

ExprId ExprPool::Unary(Op op, ExprId a) {
  if (op == Op::kNeg) return Neg(a);
  if (IsConst(a) && std::isfinite(ApplyUnary(op, ConstValue(a)))) return Const(ApplyUnary(op, ConstValue(a)));
  if (op == Op::kNot && node(a).op == Op::kNot && IsTruthValued(ExprId(node(a).a))) return ExprId(node(a).a);
  Node m;
  m.op = op;
  m.a = a.value();
  return Intern(m);
}

ExprId ExprPool::Binary(Op op, ExprId a, ExprId b, uint8_t flags) {
  const bool ca = IsConst(a), cb = IsConst(b);
  if (ca && cb) {
    // 0/0, 1/0, 0^-1, 1e308*10 stay a node (kSingular) so that the build names them.
    const double v = ApplyBinary(op, ConstValue(a), ConstValue(b));
    if (std::isfinite(v)) return Const(v);
  }
  // The identities below drop an operand or fold to a number: never one that is not finite.
  // (Two constants here are such an operation: their value is not finite.)
  const bool singular = (ca && cb) || IsSingular(a) || IsSingular(b);
  switch (op) {
    case Op::kAdd:
      if (IsConst(a, 0)) return b;
      if (IsConst(b, 0)) return a;
      if (node(b).op == Op::kNeg) return Sub(a, ExprId(node(b).a));
      if (node(a).op == Op::kNeg) return Sub(b, ExprId(node(a).a));
      break;
    case Op::kSub:
      if (IsConst(b, 0)) return a;
      if (IsConst(a, 0)) return Neg(b);
      if (a == b && !singular) return zero_;
      if (node(b).op == Op::kNeg) return Add(a, ExprId(node(b).a));
      break;
    case Op::kMul:
      if ((IsConst(a, 0) || IsConst(b, 0)) && !singular) return zero_;
      if (IsConst(a, 1)) return b;
      if (IsConst(b, 1)) return a;
      if (IsConst(a, -1)) return Neg(b);
      if (IsConst(b, -1)) return Neg(a);
      if (node(a).op == Op::kNeg && node(b).op == Op::kNeg) {
        return Mul(ExprId(node(a).a), ExprId(node(b).a));
      }
      if (node(a).op == Op::kNeg) return Neg(Mul(ExprId(node(a).a), b));
      if (node(b).op == Op::kNeg) return Neg(Mul(a, ExprId(node(b).a)));
      break;
    case Op::kDiv:
      if (IsConst(a, 0) && !singular) return zero_;
      if (IsConst(b, 1)) return a;
      if (IsConst(b, -1)) return Neg(a);
      if (node(a).op == Op::kNeg) return Neg(Div(ExprId(node(a).a), b));
      break;
    case Op::kPow:
      if (IsConst(b, 1)) return a;
      if (IsConst(b, 0) && !singular) return one_;
      break;
    case Op::kAnd:
      // The shortcuts keep an operand as the result only when it is already 0 or 1.
      if (IsConst(a) && (ConstValue(a) == 0 || IsTruthValued(b))) return ConstValue(a) != 0 ? b : zero_;
      if (IsConst(b) && (ConstValue(b) == 0 || IsTruthValued(a))) return ConstValue(b) != 0 ? a : zero_;
      break;
    case Op::kOr:
      if (IsConst(a) && (ConstValue(a) != 0 || IsTruthValued(b))) return ConstValue(a) != 0 ? one_ : b;
      if (IsConst(b) && (ConstValue(b) != 0 || IsTruthValued(a))) return ConstValue(b) != 0 ? one_ : a;
      break;
    default:
      break;
  }
  if (IsCommutative(op) && b < a) std::swap(a, b);
  Node m;
  m.op = op;
  m.a = a.value();
  m.b = b.value();
  m.flags = IsRelation(op) ? flags : 0;
  return Intern(m);
}

ExprId ExprPool::If(ExprId cond, ExprId then_value, ExprId else_value) {
  if (IsConst(cond)) return ConstValue(cond) != 0 ? then_value : else_value;
  if (then_value == else_value) return then_value;
  Node m;
  m.op = Op::kIf;
  m.a = cond.value();
  m.b = then_value.value();
  m.c = else_value.value();
  return Intern(m);
}

ExprId ExprPool::NoEvent(ExprId root) {
  if (!(mask(root) & kHasRelation)) return root;
  // Bottom-up with an explicit stack: an elseif chain or a substituted chain may be deep.
  std::unordered_map<uint32_t, ExprId> done;
  std::vector<uint32_t> stack{root.value()};
  while (!stack.empty()) {
    const uint32_t id = stack.back();
    const Node n = nodes_[id];  // a copy: interning below may move the nodes
    if (done.count(id)) {
      stack.pop_back();
      continue;
    }
    const int arity = Arity(n.op);
    if (!(n.mask & kHasRelation) || arity == 0) {
      done.emplace(id, ExprId(id));
      stack.pop_back();
      continue;
    }
    const uint32_t kids[3] = {n.a, n.b, n.c};
    bool ready = true;
    for (int k = 0; k < arity; ++k) {
      if (!done.count(kids[k])) {
        stack.push_back(kids[k]);
        ready = false;
      }
    }
    if (!ready) continue;
    stack.pop_back();
    ExprId r;
    if (arity == 1) {
      r = Unary(n.op, done.at(n.a));
    } else if (arity == 2) {
      r = Binary(n.op, done.at(n.a), done.at(n.b),
                 IsRelation(n.op) ? static_cast<uint8_t>(n.flags | kNoEvent) : 0);
    } else {
      r = If(done.at(n.a), done.at(n.b), done.at(n.c));
    }
    done.emplace(id, r);
  }
  return done.at(root.value());
}

}  // namespace momenta
