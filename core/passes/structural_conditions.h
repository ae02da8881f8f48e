#pragma once
/// Structural parameters: an if-expression whose condition depends only on Boolean and Integer
/// parameters (MSL's `exact`, `useSupport`, `useHeatPort`) chooses between different equations,
/// not between values, so the branch is fixed when the model is built — as a Modelica tool
/// evaluates such parameters — before index reduction looks at the structure. The parameters
/// (and the ones their values come from) are recorded as structural: `-p` on them needs a new
/// build. Initial equations that become `0 = 0` are dropped; a continuous equation that does is
/// left for the structural analysis to report.

#include <vector>

#include "core/passes/equation_system.h"

namespace momenta {

/// Folds the structural if-expressions of `sys` with the parameter values `params`; returns how
/// many conditions were fixed.
size_t FoldStructuralConditions(EquationSystem* sys, const std::vector<double>& params);

}  // namespace momenta
