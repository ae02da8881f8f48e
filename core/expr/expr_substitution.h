#pragma once
/// Rewriting expressions: leaves replaced by expressions (a Substitution, the passes' record of
/// what they eliminated), or any nodes by a map. Nodes whose operands come back unchanged are
/// kept, so a rewrite makes new nodes only on the paths to what it replaced.

#include <cstddef>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "core/expr/expr.h"

namespace momenta {

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

}  // namespace momenta
