#pragma once
/// Modelica's inner/outer for the 3-D library's world: a type that declares `outer: {world: World}`
/// has the world's parameters as its own (`world.g`, `world.n[2]`; core/lang/records.h); here each
/// instance's are bound to the parameters of the model's component `world`, so `-p world.g=…`
/// reaches every body. A model without that component keeps the type's defaults (the MSL's world).
/// A component `world` of another type is a model error naming both.

#include "core/flatten/flatten_context.h"

namespace momenta::flatten_internal {

void ResolveOuters(FlattenContext* context);

}  // namespace momenta::flatten_internal
