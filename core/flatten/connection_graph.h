#pragma once
/// The virtual connection graph of overdetermined connectors (Modelica 3.5, section 9.4), on
/// trees: which component defines the orientation of each set of connected frames. Nodes are the
/// connection sets of record potentials (a frame's `R`); edges the types' `branches:` (a joint
/// defines one end's orientation from the other's). Roots are every definite root (`roots:`, a
/// World) and, in a part of the graph without one, the potential root (`potential_roots:`, a free
/// body) of lowest priority, ties by the order of the components. From the roots a spanning tree
/// decides, for each instance, the hidden Boolean parameters its equations' `isRoot(frame_a.R)`
/// and `rooted(frame_a.R)` stand for (core/lang/records.h), before the structural conditions are
/// folded. A part of the graph with two definite roots, a branch that closes a loop, or a part
/// with no root at all is a model error naming the components.

#include "core/flatten/flatten_context.h"

namespace momenta::flatten_internal {

/// Decides the graph of `context`'s flat system (after its connections and the parameters'
/// order) and sets the predicates' parameters; nothing when no type declares roots or branches.
void ResolveConnectionGraph(FlattenContext* context);

}  // namespace momenta::flatten_internal
