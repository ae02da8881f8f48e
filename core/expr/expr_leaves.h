#pragma once
/// Which leaves an expression holds: the distinct variables, derivatives, pre-values and
/// parameters below a node, found by iterative walks (core/expr/expr_walk.h) that skip every
/// subtree whose leaf mask lacks the kinds asked for.

#include <cstdint>
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

}  // namespace momenta
