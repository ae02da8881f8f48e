#pragma once
/// The two stateSelect priorities that are promises rather than preferences, checked once the
/// states are known (MSL semantics): a variable with `stateSelect: always` must be a state (or an
/// alias of one), and one with `stateSelect: never` should not be. Dummy-derivative selection
/// (dummy_derivatives.h) already honours both where it has a choice and reports an `always` that
/// a constraint makes impossible; this check covers what it does not see: variables that never
/// appear differentiated, or that alias elimination and the linear fast path of index reduction
/// replaced.

#include <string>
#include <vector>

#include "core/passes/equation_system.h"
#include "core/passes/structural_analysis.h"

namespace momenta {

/// Throws ModelError at the variable for an `always` that is not a state; adds a warning for each
/// `never` that had to become a state.
void CheckStateSelect(const EquationSystem& sys, const Structure& structure,
                      std::vector<std::string>* warnings);

}  // namespace momenta
