#pragma once
/// The order in which CollectLeaves (core/expr/expr_leaves.h) lists leaves: by variable (or
/// parameter) index, then kind, then derivative order. The passes break their ties in this order,
/// so what they choose does not depend on node ids, which follow the order in which nodes were
/// made (the pool orders the operands of + and * by them, and a walk meets leaves in that order).

#include <vector>

#include "core/expr/expr.h"

namespace momenta {

/// Sorts distinct leaves (kVar, kDer, kPre, kParam) into that order.
void SortLeaves(const ExprPool& pool, std::vector<ExprId>* leaves);

}  // namespace momenta
