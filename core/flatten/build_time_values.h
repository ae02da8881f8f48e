#pragma once
/// The check that no expression of a flat system holds an operation on constants whose value is
/// not finite (0/0, 1/0, 0*(1/0), (x-x)/(x-x), 1e308*10, sqrt(-1)): the pool keeps such an
/// operation unfolded and marks it (NodeTrait kSingular, core/expr/expr.h), and the build refuses
/// it here, where the equation, when-clause or output that holds it is still known.

#include "core/flatten/flat_system.h"

namespace momenta {

/// Throws ModelError at the file:line of the first equation, initial equation, when-clause,
/// impact or output holding such an operation, naming the operation and its value. Costs one
/// look at each root (the trait is kept by every node for its subtree).
void CheckBuildTimeValues(const FlatSystem& flat);

/// Throws ModelError at the file:line of the first when-clause whose condition is not a truth
/// value (a relation, and/or/not, a Boolean variable or parameter, initial()): `when: x` of a
/// Real x.
void CheckWhenConditions(const FlatSystem& flat);

/// Throws ModelError at the file:line of the first equation `k = e` or when-assignment to an
/// Integer k whose value e is a number that is not whole (in a sum, product, min, max or a branch
/// of an if-expression): `k = if c then 2 else 1.5`. Values computed at run time are checked
/// there (a non-whole Integer is exit 3).
void CheckIntegerValues(const FlatSystem& flat);

}  // namespace momenta
