#pragma once
/// Flattening: a model spec and the component library in, one flat system out (core/flatten/).
/// Each component type is laid out once and its equations resolved into templates of local
/// indices; each instance copies the templates with its own offsets; connection sets give the
/// potential, flow and signal equations; the model's own variables, equations and outputs follow.

#include <vector>

#include "core/flatten/flat_system.h"
#include "core/lang/model_spec.h"

namespace momenta {

/// Instantiates every component of `spec` from `library` (plus the model's define: types),
/// joins the connection sets and returns the flat system. Overrides of parameters that shape the
/// structure (count:, connection indices) are applied here; every override is also checked to name
/// a real parameter. Throws ModelError naming the file, line and the user's component.
/// With `defer_equations` (the build's choice), the component equations that can wait are left
/// to FlatSystem::deferred.
FlatSystem Flatten(const ModelSpec& spec, const Library& library,
                   const ParameterOverrides& overrides, bool defer_equations = false);

/// Evaluates every parameter (bindings in order, overrides replacing bindings) and checks the
/// declared ranges and finiteness. Throws ModelError naming the parameter and where it was set.
std::vector<double> EvaluateParameters(const FlatSystem& flat, const ParameterOverrides& overrides);

}  // namespace momenta
