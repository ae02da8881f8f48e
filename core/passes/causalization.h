#pragma once
/// Causalisation: an algebraic unknown whose matched equation is linear in it (with a numeric or
/// parameter coefficient) is computed from that equation and substituted into the rest, in
/// dependency order (strongly connected components of the matching). What stays for IDA is the
/// states and the algebraic loops: a spring-damper chain becomes 2n equations, as one would write
/// it by hand.

#include "core/passes/equation_system.h"
#include "core/passes/structural_analysis.h"

namespace momenta {

struct CausalStats {
  size_t inlined = 0;
  size_t algebraic_loops = 0;       ///< components of more than one equation, kept for IDA
  size_t loop_variables = 0;
};

EquationSystem Causalize(EquationSystem sys, Structure* structure, CausalStats* stats);

}  // namespace momenta
