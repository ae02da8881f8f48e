#pragma once
/// Structural analysis: which variables are states, which equation determines which unknown
/// (maximum matching), and a clear report in the user's names when the model is unbalanced,
/// structurally singular or of index above 1.

#include <string>
#include <vector>

#include "core/passes/equation_system.h"

namespace momenta {

struct Structure {
  std::vector<bool> is_state;            ///< by flat variable: der(x) appears (x unknown)
  std::vector<int32_t> equation_of_var;  ///< by flat variable: index into sys.equations, or -1
  std::vector<int32_t> var_of_equation;  ///< by equation: the flat variable it determines
  size_t num_states = 0;
};

/// Checks balance and structural regularity; throws ModelError listing the equations and
/// variables involved (with components and file positions) otherwise.
Structure AnalyseStructure(const EquationSystem& sys);

/// Keeps the equations of `sys` that `keep` marks (by index) and renumbers `structure`'s matching
/// to them; returns how many were dropped. For the passes that remove equations after the
/// analysis (pruning, causalisation).
size_t KeepMatchedEquations(EquationSystem* sys, Structure* structure,
                            const std::vector<bool>& keep);

}  // namespace momenta
