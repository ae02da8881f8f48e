#pragma once
/// Structural parameters: an if-expression whose condition depends only on Boolean and Integer
/// parameters (MSL's `exact`, `useSupport`, `useHeatPort`) chooses between different equations,
/// not between values, so the branch is fixed when the model is built — as a Modelica tool
/// evaluates such parameters — before index reduction looks at the structure. The parameters
/// (and the ones their values come from) are recorded as structural: `-p` on them needs a new
/// build. So are the parameters declared `evaluate: true` (Modelica's `Evaluate = true`) and those
/// bound to them alone: their values become constants, and a product with a zero one drops out
/// (`i = C*der(v)` with C = 0 is `i = 0`: v is no state). Initial equations that become `0 = 0`
/// are dropped; a continuous equation that does is left for the structural analysis to report.

#include <vector>

#include "core/passes/equation_system.h"

namespace momenta {

/// Folds the structural if-expressions and the evaluated parameters of `sys` with the parameter
/// values `params`; returns how many conditions and parameters were fixed.
size_t FoldStructuralConditions(EquationSystem* sys, const std::vector<double>& params);

}  // namespace momenta
