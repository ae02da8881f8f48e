#pragma once
/// What a build reports, which `momenta check` prints: each pass's name, time and the system's
/// size after it, with a note saying what the pass did, and the words the build has for the user
/// (warnings, notes, the states, what index reduction chose). Each note is written here from its
/// pass's own statistics, so that the wording of `check` lives in one place and the passes and
/// the compiler know nothing of reports.

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "core/compile/compiled_model.h"
#include "core/lang/model_spec.h"
#include "core/passes/alias_elimination.h"
#include "core/passes/causalization.h"
#include "core/passes/discrete_partition.h"
#include "core/passes/dummy_derivatives.h"
#include "core/passes/equation_system.h"
#include "core/passes/index_reduction.h"
#include "core/passes/pantelides.h"
#include "core/passes/pruning.h"
#include "core/passes/structural_analysis.h"

namespace momenta {

struct PassReport {
  std::string name;
  double seconds = 0;      ///< wall-clock time
  double cpu_seconds = 0;  ///< CPU time of the building thread (leaves out waiting for a core)
  size_t variables = 0;  ///< unknowns after the pass
  size_t equations = 0;  ///< equations after the pass
  std::string note;
};

struct BuildReport {
  std::vector<PassReport> passes;
  std::vector<std::string> warnings;
  std::vector<std::string> notes;       ///< what was accepted but deserves a word (redundant initial conditions)
  std::vector<std::string> pruned;      ///< names of pruned variables
  std::vector<std::string> states;      ///< names of the states
  /// The free signal inputs held as inputs (BuildOptions::hold_free_inputs), in the model's order.
  std::vector<std::string> inputs;
  size_t num_components = 0, num_parameters = 0;
  /// Index reduction (Pantelides and dummy derivatives), when the model needed it.
  uint32_t structural_index = 1;
  std::vector<std::string> differentiated;      ///< differentiated equations, described
  std::vector<std::string> dummy_derivatives;   ///< e.g. "der(pendulum.y)"
  std::vector<std::string> state_choices;       ///< where a choice of states was made
  /// The -p values the model was built with: those given with a unit converted to their
  /// parameters' declared units (what ModelState::SetParameters takes).
  ParameterOverrides overrides;
};

// ---- each pass's note, from its statistics ------------------------------------------------------

std::string FlattenNote(const FlatSystem& flat);
std::string StructuralParametersNote(size_t folded_conditions, size_t absent_connectors, size_t absent_parts = 0);
std::string AliasEliminationNote(const AliasStats& stats);
std::string IndexReductionNote(const IndexStats& stats);
/// With the system's when-clauses and impacts, which the partition sets apart too.
std::string DiscretePartitionNote(const DiscreteStats& stats, const EquationSystem& sys);
/// `derivative_aliases`: SubstituteDerivativeAliases' count after the dummy derivatives.
std::string PantelidesNote(const DifferentiatedSystem& differentiated,
                           const StateSelection& selection, size_t derivative_aliases);
std::string StructuralAnalysisNote(const Structure& structure);
std::string PruningNote(const PruneStats& stats);
std::string CausalisationNote(const CausalStats& stats);
std::string CompilationNote(const CompiledModel& model);

// ---- what the user reads besides the notes ------------------------------------------------------

/// Records what Pantelides' algorithm and the dummy derivatives did to `sys`: the structural
/// index, the differentiated equations, the dummy derivatives, the choices of states and the
/// warnings about them.
void ReportIndexReduction(const EquationSystem& sys, const DifferentiatedSystem& differentiated,
                          const StateSelection& selection, BuildReport* report);

/// Records what compilation found: the states, the redundant initial conditions left out (a
/// note each, the first few) and the start values taken for missing ones (a warning).
void ReportCompiledModel(const CompiledModel& model, BuildReport* report);

}  // namespace momenta
