#pragma once
/// Derivatives by the chain rule: partial derivatives with respect to one leaf or to each leaf
/// of an expression in turn (a Jacobian row), and the time derivative (index reduction).

#include <cstdint>
#include <memory>
#include <vector>

#include "core/expr/expr.h"

namespace momenta {

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

}  // namespace momenta
