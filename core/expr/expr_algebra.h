#pragma once
/// Symbolic algebra on the expression pool: substitution of leaves, partial and time derivatives
/// (chain rule), leaf collection, affine decomposition and solving an equation for one leaf.
/// Every traversal here is iterative (explicit stack), so a 100 000-deep expression — a chain of
/// rods whose offsets add up — cannot overflow the call stack.

#include <functional>
#include <memory>
#include <string>
#include <unordered_map>
#include <vector>

#include "core/expr/expr.h"

namespace momenta {

/// The distinct leaves of kinds in `mask` (kHasVar, kHasDer, kHasPre, kHasParam) below `e`.
std::vector<ExprId> CollectLeaves(const ExprPool& pool, ExprId e, uint8_t mask);

/// True when the leaf `leaf` occurs below `e`.
bool ContainsLeaf(const ExprPool& pool, ExprId e, ExprId leaf);

/// True when every leaf of kinds in `mask` (kHasVar, kHasDer, kHasPre, kHasParam) below `e` has
/// its variable (or parameter) in `members`; the walk stops at the first that has not.
bool AllLeavesIn(const ExprPool& pool, ExprId e, uint8_t mask, const std::vector<bool>& members);

/// The distinct leaves of kinds in `mask` below `e`, appended to `out` (cleared first): the form
/// for loops over many equations, which then reuse one buffer.
void CollectLeaves(const ExprPool& pool, ExprId e, uint8_t mask, std::vector<ExprId>* out);

/// Replaces leaves by expressions. A replacement is itself rewritten (so chains x->y->z resolve),
/// which requires the map to be acyclic. Results are memoised until the map changes.
class Substitution {
 public:
  explicit Substitution(ExprPool* pool) : pool_(pool) {}
  void Set(ExprId leaf, ExprId replacement);
  bool Has(ExprId leaf) const;
  /// `e` with every mapped leaf replaced; `e` itself, and no new node, when none occurs in it.
  ExprId Apply(ExprId e);
  /// True when some mapped leaf occurs below `e`, i.e. Apply(e) may differ from `e`. A walk
  /// without the memo's writes: passes that rewrite many equations of which few hold a
  /// replaced leaf check first.
  bool Touches(ExprId e) const;
  size_t size() const { return num_entries_; }
  /// Gives back the memo (8 bytes per pool node up to the largest rewritten): it serves one
  /// batch of Apply calls (it is void after the next Set anyway), while the map of an
  /// accumulated substitution lives on through compilation, the peak of the build's memory.
  void ReleaseMemo();

 private:
  /// The replacement of leaf `id` (node `n`), or an invalid id.
  ExprId Replacement(uint32_t id, const Node& n) const;
  /// The table that holds replacements of leaves like `n` (by n.a), or null for the others.
  const std::vector<ExprId>* Table(const Node& n) const;

  ExprPool* pool_;
  /// Replacements by the leaf's variable (values, first derivatives, pre-values) or parameter: a
  /// few bytes per variable, where one array by node id took 4 bytes per pool node. Other
  /// leaves (higher derivatives, constants) by node id in `other_`. Invalid = keep.
  std::vector<ExprId> by_var_, by_der_, by_pre_, by_param_;
  std::unordered_map<uint32_t, ExprId> other_;
  std::vector<ExprId> memo_;       ///< by node id
  std::vector<uint32_t> memo_gen_;
  uint32_t gen_ = 1;
  size_t num_entries_ = 0;
  /// The LeafMask kinds of the mapped leaves: a subtree without any of them is unchanged.
  uint8_t mapped_kinds_ = 0;
};

/// `e` with the nodes in `map` (node id -> replacement) replaced; only subtrees whose leaf mask
/// meets `mask` are visited.
ExprId ReplaceNodes(ExprPool* pool, ExprId e, const std::unordered_map<uint32_t, ExprId>& map,
                    uint8_t mask);

/// `e` with one leaf replaced by `value` (for one-off rewrites; Substitution is for many).
ExprId ReplaceLeaf(ExprPool* pool, ExprId e, ExprId leaf, ExprId value);

/// d e / d leaf, where leaf is a kVar, kDer or kParam node (other leaves are constants).
ExprId PartialDerivative(ExprPool* pool, ExprId e, ExprId leaf);

/// The partial derivatives of one expression with respect to several of its leaves (a Jacobian
/// row), one leaf at a time: Of(leaf) is PartialDerivative(pool, e, leaf), node for node, for
/// less work, except for nodes PartialDerivative makes and nothing reads. The expression is
/// walked once (Reset); each partial then visits only the nodes above its leaf. The nodes
/// without the leaf have the derivative 0 and make no nodes, nor does a/b's b*b when b' = 0.
class PartialDerivatives {
 public:
  explicit PartialDerivatives(ExprPool* pool);
  ~PartialDerivatives();
  /// Takes `e`, whose leaves of the kinds in `mask` (kHasVar, kHasDer, kHasParam) are asked for.
  void Reset(ExprId e, uint8_t mask);
  /// The distinct leaves of those kinds below `e`, in CollectLeaves' order (for a Jacobian row;
  /// usually found by Reset's walk, without walking again).
  const std::vector<ExprId>& Leaves();
  /// d e / d leaf for a leaf of those kinds; 0 where it occurs only in if-conditions or not at all.
  ExprId Of(ExprId leaf);

 private:
  struct Walk;
  ExprPool* pool_;
  std::unique_ptr<Walk> walk_;
};

/// d e / d time by the chain rule: x -> der(x), der(x) -> der(der(x)), time -> 1, parameters and
/// pre() -> 0. The condition of an if-expression is piecewise constant (an event relation): each
/// branch is differentiated.
ExprId TimeDerivative(ExprPool* pool, ExprId e);

/// e = sum(coef_k * leaf_k) + offset, with numeric coefficients and a parameter-only offset.
/// The leaf kinds an alias equation never holds: derivatives, pre-values, time, initial() and
/// conditions (alias elimination; the sure aliases of core/flatten/equation_template.h).
constexpr uint8_t kNeverAliasLeaves = kHasDer | kHasPre | kHasTime | kHasInitial | kHasCond;

struct AffineForm {
  std::vector<std::pair<ExprId, double>> terms;  ///< leaf (kVar or kDer) and its coefficient
  ExprId offset;
};

/// Decomposes `e` as an AffineForm; false when `e` is not affine in its variables with numeric
/// coefficients, or has more than `max_terms` terms.
bool DecomposeAffine(ExprPool* pool, ExprId e, size_t max_terms, AffineForm* out);

/// Solves `residual = 0` for `leaf` when the residual is linear in it: residual = a*leaf + b with a
/// free of `leaf`. With `param_coefficient_ok`, `a` may be a parameter expression (its value is
/// then checked for zero at run time: see *coefficient); otherwise `a` must be a nonzero number.
/// Returns an invalid id when the equation cannot be solved this way.
ExprId SolveFor(ExprPool* pool, ExprId residual, ExprId leaf, bool param_coefficient_ok,
                ExprId* coefficient);

/// Names for printing leaves.
struct ExprNamer {
  std::function<std::string(uint32_t)> var;
  std::function<std::string(uint32_t)> param;
};

/// Infix text of an expression (for `momenta check` and messages); deep trees are elided.
std::string ToString(const ExprPool& pool, ExprId e, const ExprNamer& names);

}  // namespace momenta
