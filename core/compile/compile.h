#pragma once
/// The last pass: the DAE for IDA (unknowns in declaration order, each with its matched
/// equation), the initialisation system (fixed start values and initial equations, completed
/// with start values of states nothing fixes), the event machinery (frozen conditions and their
/// zero-crossing functions, discrete equations, when-clauses, impacts), and the compiled programs
/// for all of it.

#include <memory>
#include <string>
#include <vector>

#include "core/build.h"
#include "core/compile/compiled_model.h"
#include "core/passes/equation_system.h"
#include "core/passes/structural_analysis.h"

namespace momenta {

std::shared_ptr<CompiledModel> CompileModel(EquationSystem sys, const Structure& st,
                                            const std::vector<std::string>& output_names,
                                            BuildReport* report);

}  // namespace momenta
