#pragma once
/// The last pass: the DAE for IDA (unknowns in declaration order, each with its matched
/// equation), the initialisation system (fixed start values and initial equations, completed
/// with start values of states nothing fixes), the event machinery (frozen conditions and their
/// zero-crossing functions, discrete equations, when-clauses, impacts), and the compiled programs
/// for all of it. Its stages are core/compile/compile_stages.h; what it reports to the user
/// (states, redundant and missing initial conditions) the build reads off the compiled model
/// (core/build_report.h).

#include <memory>
#include <string>
#include <vector>

#include "core/compile/compiled_model.h"
#include "core/passes/equation_system.h"
#include "core/passes/structural_analysis.h"

namespace momenta {

/// Compiles `sys` with its causal structure (`structure`: states and each unknown's matched
/// equation); `output_names` name `sys.outputs`. Throws ModelError when the initial conditions
/// leave unknowns undetermined, or a when-clause assigns or reinitialises what it cannot.
std::shared_ptr<CompiledModel> CompileModel(EquationSystem sys, const Structure& structure,
                                            const std::vector<std::string>& output_names);

}  // namespace momenta
