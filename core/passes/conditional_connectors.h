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
/// A conditional part of a composite type (`condition: use_r and use_v`, as Modelica's
/// `Der derv[3] if use_r and use_v`) is resolved the same way, on its condition's value:
///   - absent, its equations, initial equations, when-clauses and impacts go (its own parts' too),
///     and so does every connection to it inside the composite: an equality whose member is its
///     connector goes, its flows leave the flow sums; a connection that would leave a connector
///     that exists without a driver or reference is an error naming both;
///   - its variables drop out as constants; an equation of the composite, a model equation or an
///     output that names them is an error.
/// The condition parameters (a part's: every parameter its condition reads, Real ones too) are
/// recorded as structural: `-p` on them needs a new build.

#include <vector>

#include "core/passes/equation_system.h"

namespace momenta {

/// Resolves the conditional connectors and parts of `sys` with the parameter values `params`;
/// returns how many connectors are absent, and sets `absent_parts` (when given) to how many parts are.
size_t ResolveConditionalConnectors(EquationSystem* sys, const std::vector<double>& params,
                                    size_t* absent_parts = nullptr);

}  // namespace momenta
