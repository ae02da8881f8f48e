#pragma once
/// Conditional connectors (docs/FORMAT.md, "Conditional connectors"): a connector declared with
/// `condition: useHeatPort` exists only when that Boolean parameter of its component is true, as
/// MSL's `HeatPort heatPort if useHeatPort`. Flattening keeps the connector's variables either
/// way; this pass, run on the parameter values after the structural if-expressions are folded,
/// makes an absent connector disappear:
///   - a connection naming it is an error naming the component and the parameter;
///   - the component's equations (and initial equations) that still name its variables are left
///     out: they are the ones that hold only with the connector (`heatPort.Q_flow = -lossPower`);
///   - its variables drop out as constants: zero (its flows' `= 0 (unconnected)` go with them);
///   - a model equation or output that names its variables is an error.
/// The condition parameters are recorded as structural: `-p` on them needs a new build.

#include <vector>

#include "core/passes/equation_system.h"

namespace momenta {

/// Resolves the conditional connectors of `sys` with the parameter values `params`; returns how
/// many are absent.
size_t ResolveConditionalConnectors(EquationSystem* sys, const std::vector<double>& params);

}  // namespace momenta
