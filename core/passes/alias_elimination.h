#pragma once
/// Alias elimination: equations `a = b`, `a = -b`, `a = ±b + c` and `a = c`, with c a parameter
/// expression, remove a variable and an equation each. Connections produce most of them (equal
/// potentials, flows summing to zero over two connectors), so most of a flat model goes here.

#include "core/passes/equation_system.h"

namespace momenta {

struct AliasStats {
  size_t aliases = 0;    ///< variables replaced by ±another + offset
  size_t constants = 0;  ///< variables replaced by a parameter expression
};

/// Removes every alias equation. The variable that stays of an alias set is, in order of
/// preference: one whose derivative appears, one with `stateSelect: prefer`, the first declared.
/// The build's first call passes the flattening's `deferred` equations (their residuals in `sys`
/// are invalid): it reads one form per template, and makes only the equations that stay, with
/// the aliases substituted; every equation in the system it returns is made. `leaves`, when
/// given, holds the equations' leaves (ReduceIndex's, from the round before; collected here when
/// not valid) and is kept current.
EquationSystem EliminateAliases(EquationSystem sys, AliasStats* stats,
                                const DeferredEquations* deferred = nullptr,
                                EquationLeaves* leaves = nullptr);

}  // namespace momenta
