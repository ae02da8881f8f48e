#pragma once
/// The connection sets inside a composite type, written once per type as equations of its layout
/// (templates over its local variables) that every instance copies.

#include <vector>

#include "core/flatten/composite_parts.h"
#include "core/flatten/type_layout.h"

namespace momenta::flatten_internal {

/// Joins the connections of `layout`'s type: between its parts' connectors (inside) and its own
/// (outside, named alone). Potentials are equal; the flows of inside connectors less those of
/// outside ones sum to zero (Modelica's rule); an inside connector connected to nothing has zero
/// flows; a signal set has exactly one driver (an inside output or an outside input). Appends the
/// equations to `layout`, records in it which parts' connectors are connected, and sets each
/// plan's first_slot.
void InnerConnections(TypeLayout* layout, std::vector<PartPlan>* plans);

}  // namespace momenta::flatten_internal
