#pragma once
/// The expression pool: every equation, parameter binding and derivative of a model is a node of
/// one hash-consed DAG. Identical subexpressions are one node, so common subexpressions are shared
/// by construction and equality of ids is structural equality. Constructors fold constants and
/// apply the identities x+0, x*1, x*0, -(-x), x-x, so derived expressions (symbolic Jacobians,
/// substitutions) stay small. The identities assume finite operands: variables and parameters are
/// checked to be finite at run time, and an operation on constants whose value is not finite stays
/// a node of its own, marked kSingular, that no identity drops.

#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "core/base/huge_alloc.h"
#include "core/base/ids.h"
#include "core/expr/ops.h"

namespace momenta {

/// Bits of Node::flags.
enum NodeFlag : uint8_t {
  kNoEvent = 1,  ///< a relation inside noEvent(): it never becomes a zero-crossing function
};

/// Bits of the leaf-kind mask each node carries: which kinds of leaf its subtree holds.
enum LeafMask : uint8_t {
  kHasVar = 1,
  kHasDer = 2,
  kHasTime = 4,
  kHasParam = 8,
  kHasPre = 16,
  kHasRelation = 32,
  kHasInitial = 64,
  kHasCond = 128,
};

/// Bits of Node::traits, derived like the mask from the subtree.
enum NodeTrait : uint8_t {
  /// The subtree holds a division by the constant zero (x/0) or an operation on constants only
  /// whose value is not finite (0/0, 1e308*10, sqrt(-1)): the pool keeps it unfolded, and folds no identity (x*0, 0/x, x-x, x^0)
  /// that would drop it, so that the build can name it (CheckBuildTimeValues).
  kSingular = 1,
  /// The subtree holds an if-expression (a structural condition may fold it: FoldStructuralConditions).
  kHasIf = 2,
};

/// One node of the pool: 16 bytes, so that four share a cache line. The operands (a, b, c) are
/// node ids or payloads as Op says; a constant's value is held in b and c, and a table leaf's
/// column count and column in c (TableColumns, TableColumn).
struct Node {
  Op op = Op::kConst;
  uint8_t flags = 0;
  uint8_t mask = 0;  ///< LeafMask bits of the subtree
  uint8_t traits = 0;  ///< NodeTrait bits of the subtree (not part of the node's identity)
  uint32_t a = 0, b = 0, c = 0;

  /// kConst: the number.
  double value() const {
    const uint64_t bits = static_cast<uint64_t>(b) | static_cast<uint64_t>(c) << 32;
    double v;
    std::memcpy(&v, &bits, sizeof v);
    return v;
  }
  void set_value(double v) {
    uint64_t bits;
    std::memcpy(&bits, &v, sizeof bits);
    b = static_cast<uint32_t>(bits);
    c = static_cast<uint32_t>(bits >> 32);
  }
  /// kTable: the table's number of columns (at most kMaxTableColumns) and the column read (1-based).
  uint32_t TableColumns() const { return c & 0xFFFFu; }
  uint32_t TableColumn() const { return c >> 16; }
};
static_assert(sizeof(Node) == 16, "a node is 16 bytes");

/// The most columns a table may have (a table leaf keeps its column count and column in 16 bits each).
constexpr uint32_t kMaxTableColumns = 0xFFFF;

/// Owner of all expression nodes of one model. Ids stay valid while the pool lives; the pool only
/// grows.
class ExprPool {
 public:
  ExprPool();

  ExprId Const(double v);
  ExprId Var(VarId v) { return Leaf(Op::kVar, v.value()); }
  /// The `order`-th time derivative of `v`. Orders above 1 exist only until index reduction
  /// turns them into variables of their own (dummy derivatives, or states of a first-order form).
  ExprId Der(VarId v, uint32_t order = 1);
  ExprId Pre(VarId v) { return Leaf(Op::kPre, v.value()); }
  ExprId Param(ParamId p) { return Leaf(Op::kParam, p.value()); }
  ExprId Time() { return time_; }
  ExprId Initial() { return Leaf(Op::kInitial, 0); }
  ExprId Cj() { return Leaf(Op::kCj, 0); }
  ExprId Cond(uint32_t index) { return Leaf(Op::kCond, index); }
  /// Column `column` (1-based) of the rows × cols table whose elements are the consecutive
  /// parameters from `first`, row by row.
  ExprId Table(ParamId first, uint32_t rows, uint32_t cols, uint32_t column);
  ExprId Zero() const { return zero_; }
  ExprId One() const { return one_; }

  ExprId Add(ExprId a, ExprId b);
  ExprId Sub(ExprId a, ExprId b);
  ExprId Mul(ExprId a, ExprId b);
  ExprId Div(ExprId a, ExprId b);
  ExprId Pow(ExprId a, ExprId b);
  ExprId Neg(ExprId a);
  /// A function of one argument (kSin … kSign, kFloor) or the logical kNot.
  ExprId Unary(Op op, ExprId a);
  /// Any two-argument operation: arithmetic, atan2/min/max, relations, and/or.
  ExprId Binary(Op op, ExprId a, ExprId b, uint8_t flags = 0);
  ExprId If(ExprId cond, ExprId then_value, ExprId else_value);
  /// The same node with the kNoEvent flag on every relation of its subtree.
  ExprId NoEvent(ExprId e);

  /// The leaf (kVar, kDer, kPre, kParam) if some expression already holds it; invalid otherwise.
  /// Lets passes skip rewriting leaves that occur nowhere, without creating them.
  ExprId FindLeaf(Op op, uint32_t payload) const;

  /// Sizes the hash table for `nodes` nodes now, so that growing to that many does not rehash it
  /// later (a rehash holds the old and the new table at once: done early, that is not at the
  /// build's peak).
  void Reserve(size_t nodes);

  const Node& node(ExprId id) const { return nodes_[id.value()]; }
  Op op(ExprId id) const { return nodes_[id.value()].op; }
  size_t size() const { return nodes_.size(); }

  bool IsConst(ExprId id) const { return op(id) == Op::kConst; }
  /// The value is 0 or 1 by construction (a relation, and/or/not, or the constants 0 and 1).
  bool IsTruthValued(ExprId id) const;
  bool IsConst(ExprId id, double v) const;
  double ConstValue(ExprId id) const { return node(id).value(); }
  /// No variables, derivatives, pre-values, time or initial(): a function of parameters only.
  bool IsParamOnly(ExprId id) const {
    return (node(id).mask & (kHasVar | kHasDer | kHasTime | kHasPre | kHasInitial | kHasCond)) == 0;
  }
  uint8_t mask(ExprId id) const { return node(id).mask; }
  /// The subtree holds an operation on constants whose value is not finite (NodeTrait kSingular).
  bool IsSingular(ExprId id) const { return node(id).traits & kSingular; }
  /// The subtree holds an if-expression (NodeTrait kHasIf).
  bool HasIf(ExprId id) const { return node(id).traits & kHasIf; }
  /// The order of a kDer leaf (1 for der(x), 2 for der(der(x)), …).
  uint32_t DerOrder(ExprId id) const { return node(id).b + 1; }

 private:
  ExprId Leaf(Op op, uint32_t payload);
  /// The NodeTrait bits of a node about to be interned.
  uint8_t Traits(const Node& n) const;
  ExprId Intern(const Node& n);
  void Rehash(size_t slots);
  /// Looks for a node equal to `n` (hash tag `tag`) in an open-addressing table of `size` slots;
  /// sets *found when there is one. Returns the slot the probe stopped at (empty when not found).
  size_t Probe(const uint64_t* table, size_t size, uint32_t tag, const Node& n, ExprId* found) const;
  /// Whether a child of `n` is in the nursery (made since its last move into table_).
  bool ChildrenAreYoung(const Node& n) const;
  /// Moves the nursery's entries into table_ and empties it.
  void Mature();

  GrowableArray<Node> nodes_;
  /// Open-addressing hash table with linear probing, grown by half when three quarters full: each
  /// slot holds (hash tag << 32) | node id, or kEmptySlot. The tag spares a probe the node
  /// comparison (a cache miss) unless it is a likely match.
  std::vector<uint64_t, HugePageAllocator<uint64_t>> table_;
  size_t table_used_ = 0;
  /// The nursery: the entries of the hashed nodes made since young_first_, in a table small
  /// enough to stay in cache, moved into table_ in one prefetched batch when half full. Most new
  /// nodes are built on a node just made (a sum over a product made a moment ago); an equal node
  /// would be younger than that child, so it is in the nursery, and such a node never probes
  /// table_. On the 100 003-component chain that spares 2.5 of 6 million probes of table_.
  static constexpr size_t kYoungSlots = 4096;
  /// The nursery's size in a new pool, grown fourfold at each move up to kYoungSlots.
  static constexpr size_t kFirstYoungSlots = 256;
  std::vector<uint64_t> young_;
  size_t young_used_ = 0;
  uint32_t young_first_ = 0;
  /// The leaves of variables, parameters, pre() and first derivatives by payload (0: not made
  /// yet; node 0 is the constant 0): the most frequent nodes, found by index, next to their
  /// neighbours, instead of by hash (a cache miss each in a large model). They are not in table_.
  std::vector<uint32_t> leaf_index_[4];
  ExprId zero_, one_, minus_one_, time_;
};

}  // namespace momenta
