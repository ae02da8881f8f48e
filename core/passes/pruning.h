#pragma once
/// Pruning: every equation and variable that no requested output (and no initial condition of a
/// kept variable) depends on is dropped. A sensor that nobody probes costs nothing; a subsystem
/// that no output sees is not integrated at all.

#include "core/passes/equation_system.h"
#include "core/passes/structural_analysis.h"

namespace momenta {

struct PruneStats {
  size_t variables = 0, equations = 0, initial_equations = 0;
};

/// Keeps what the outputs need. `structure` is updated to the kept equations.
EquationSystem Prune(EquationSystem sys, Structure* structure, PruneStats* stats);

}  // namespace momenta
