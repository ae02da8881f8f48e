#pragma once
/// Parameters computed at the start (Modelica's `parameter Real c(fixed = false, start = 20)`):
/// a component entry writes `c: {fixed: false, start: 20}`, and the initial conditions determine
/// c together with the states (MSL's InitSpringConstant: the spring constant that holds a pendulum
/// at rest at a given angle). Each such parameter becomes a variable of the same name with the
/// equation der(c) = 0 — an unknown of the initial problem, constant afterwards — whose start
/// guess is the parameter's value (its `start:`, or -p). A parameter whose binding reads one is
/// computed from it, so it becomes a variable too, with its binding as its equation. Every
/// equation, when-clause, impact and output that reads such a parameter reads the variable.
/// The parameter stays, holding the guess.

#include "core/flatten/flatten_context.h"

namespace momenta::flatten_internal {

/// Turns context->free_parameters (and the parameters computed from them) into variables, as
/// above. Needs FlatSystem::parameter_order. A free or dependent parameter that is structural
/// (`evaluate: true`) is a model error naming it.
void MakeFreeParametersVariables(FlattenContext* context);

}  // namespace momenta::flatten_internal
