#pragma once
/// The FMU's variables and their value references, as `momenta fmu` describes them in
/// modelDescription.xml and the runtime (fmu_instance.h) serves them: one layout computed from the
/// built model by both, so the two cannot disagree.
///
///   value references 0 .. P-1       the model's parameters (flat order), causality parameter
///   P .. P+O-1                      the model's outputs (CompiledModel::output_names)
///   then per state not an output    the state, a local variable
///   then per state                  its derivative der(NAME), a local variable
///
/// The GUID is a hash of everything an importer relies on (names, kinds, references, units, the
/// numbers of states and event indicators): it changes with the model's structure, not with a
/// parameter's value.

#include <cstdint>
#include <string>
#include <vector>

#include "core/compile/compiled_model.h"

namespace momenta::fmu {

enum class VariableKind { kParameter, kOutput, kState, kDerivative };

struct FmuVariable {
  std::string name, unit, description;
  VariableKind kind = VariableKind::kParameter;
  uint32_t value_reference = 0;
  size_t index = 0;         ///< the parameter's, output's or state's index in the model
  double start = 0;         ///< parameters: the value the FMU was exported with
  bool structural = false;  ///< a parameter that shaped the structure: fixed at export
  int state = -1;  ///< outputs and states: the state this variable is (index into state_y), or -1
};

struct FmuLayout {
  std::vector<FmuVariable> variables;                 ///< by value reference
  std::vector<uint32_t> state_refs, derivative_refs;  ///< per state
  size_t num_event_indicators = 0;  ///< the conditions' crossing functions, then one per impact
  std::string guid;
};

/// The layout of `model`, the parameters' start values `parameter_values` (ModelState's, in their
/// units).
FmuLayout MakeLayout(const CompiledModel& model, const std::vector<double>& parameter_values);

/// The model identifier made of a model's name: letters, digits and '_', not starting with a digit.
std::string ModelIdentifier(const std::string& model_name);

}  // namespace momenta::fmu
