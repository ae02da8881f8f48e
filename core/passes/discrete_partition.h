#pragma once
/// Discrete partition: the equations that define discrete variables (Boolean, Integer, and Reals
/// set at events) are taken out of the continuous system and solved explicitly, `d = value`, to be
/// evaluated at events in dependency order (pre() breaks cycles, as in Modelica). A discrete
/// variable assigned by a when-clause or an impact needs no equation; any other must have one.

#include "core/passes/equation_system.h"

namespace momenta {

struct DiscreteStats {
  size_t variables = 0, equations = 0;
};

EquationSystem PartitionDiscrete(EquationSystem sys, DiscreteStats* stats);

}  // namespace momenta
