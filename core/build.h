#pragma once
/// The pipeline from a model file's spec to a CompiledModel: flatten, eliminate aliases, reduce
/// the index, analyse, prune, causalise, set up initialisation, compile. Each pass reports its
/// size and time (what `momenta check` prints).

#include <memory>
#include <string>
#include <vector>

#include "core/compile/compiled_model.h"
#include "core/lang/model_spec.h"

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
  size_t num_components = 0, num_parameters = 0;
  /// Index reduction (Pantelides and dummy derivatives), when the model needed it.
  uint32_t structural_index = 1;
  std::vector<std::string> differentiated;      ///< differentiated equations, described
  std::vector<std::string> dummy_derivatives;   ///< e.g. "der(pendulum.y)"
  std::vector<std::string> state_choices;       ///< where a choice of states was made
  std::string compile_note;
};

/// Flattens, simplifies and compiles the model (the passes recorded in `report`). Throws
/// ModelError naming the file, line and the user's component.
std::shared_ptr<const CompiledModel> BuildModel(const ModelSpec& spec, const Library& library,
                                                const ParameterOverrides& overrides,
                                                BuildReport* report);
/// The same, releasing the spec once it is flattened: a large model's parsed file is about a
/// fifth of the build's peak memory, and nothing after flattening reads it.
std::shared_ptr<const CompiledModel> BuildModel(ModelSpec&& spec, const Library& library,
                                                const ParameterOverrides& overrides,
                                                BuildReport* report);

}  // namespace momenta
