// The build a linearisation needs (see linearization.h): the model's free signal inputs held as
// constant states, the chosen outputs and the inputs themselves as output columns, and which
// columns are which once it is built.

#include <algorithm>

#include "core/base/error.h"
#include "core/base/messages.h"
#include "core/lang/parser.h"
#include "solver/linearization.h"

namespace momenta {

namespace {

/// Every variable's name in `flat` (the names an output may take).
std::vector<std::string> VariableNames(const FlatSystem& flat) {
  std::vector<std::string> names;
  names.reserve(flat.variables.size());
  for (size_t v = 0; v < flat.variables.size(); ++v) names.push_back(flat.VariableName(VarId(static_cast<uint32_t>(v))));
  return names;
}

bool Lists(const ModelSpec& spec, const std::string& name) {
  return std::any_of(spec.outputs.begin(), spec.outputs.end(), [&](const OutputSpec& o) { return o.text == name; });
}

void AddOutput(const std::string& name, ModelSpec* spec) {
  OutputSpec o;
  o.text = name;
  o.loc = spec->loc;
  o.expr = ParseName(name, spec->loc);
  spec->outputs.push_back(std::move(o));
}

/// The index of `name` among the model's output columns.
size_t Column(const CompiledModel& model, const std::string& name) {
  const auto it = std::find(model.output_names.begin(), model.output_names.end(), name);
  MOMENTA_CHECK(it != model.output_names.end());
  return static_cast<size_t>(it - model.output_names.begin());
}

}  // namespace

void PrepareLinearizationBuild(const LinearizationSpec& spec, BuildOptions* options) {
  options->hold_free_inputs = true;
  for (const auto& [name, value] : spec.inputs) options->input_values[name] = value;
  const std::vector<std::string> outputs = spec.outputs;
  options->add_outputs = [outputs](const FlatSystem& flat, ModelSpec* model) {
    // The outputs asked for, each a variable of the model.
    std::vector<std::string> names;
    for (const std::string& name : outputs) {
      if (Lists(*model, name)) continue;
      if (names.empty()) names = VariableNames(flat);
      if (std::find(names.begin(), names.end(), name) == names.end()) {
        const std::vector<std::string> close = ClosestNames(name, names);
        throw UsageError("momenta: -y " + name + ": " + flat.model_name + " has no variable " + name +
                         (close.empty() ? "" : " (did you mean " + JoinNames(close) + "?)"));
      }
      AddOutput(name, model);
    }
    // The inputs, whose output columns tell which state each is.
    for (VarId v : flat.free_inputs) {
      const std::string name = flat.VariableName(v);
      if (!Lists(*model, name)) AddOutput(name, model);
    }
  };
}

LinearizationColumns ResolveLinearizationColumns(const CompiledModel& model, const BuildReport& report,
                                                 const LinearizationSpec& spec) {
  LinearizationColumns columns;
  std::vector<std::string> inputs;
  for (const auto& input : spec.inputs) inputs.push_back(input.first);
  if (inputs.empty()) inputs = report.inputs;
  for (const std::string& name : inputs) columns.inputs.push_back(Column(model, name));
  for (const std::string& name : report.inputs) columns.held.push_back(Column(model, name));
  if (!spec.outputs.empty()) {
    for (const std::string& name : spec.outputs) columns.outputs.push_back(Column(model, name));
    return columns;
  }
  // The model's own outputs: every column but the inputs the build added.
  for (size_t k = 0; k < model.output_names.size(); ++k) {
    const std::string& name = model.output_names[k];
    if (std::find(report.inputs.begin(), report.inputs.end(), name) == report.inputs.end()) {
      columns.outputs.push_back(k);
    }
  }
  return columns;
}

}  // namespace momenta
