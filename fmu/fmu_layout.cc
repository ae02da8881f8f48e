// The FMU's variables from the built model (fmu_layout.h).

#include "fmu/fmu_layout.h"

#include <cctype>
#include <cstdio>
#include <map>

namespace momenta::fmu {

namespace {

/// FNV-1a over the text, from `seed`.
uint64_t Fnv1a(const std::string& text, uint64_t seed) {
  uint64_t h = seed;
  for (unsigned char c : text) {
    h ^= c;
    h *= 1099511628211ull;
  }
  return h;
}

/// A GUID-shaped text of 128 bits of hash.
std::string GuidOf(const std::string& text) {
  const uint64_t a = Fnv1a(text, 14695981039346656037ull), b = Fnv1a(text, 0x9e3779b97f4a7c15ull);
  char buf[48];
  std::snprintf(buf, sizeof buf, "{%08x-%04x-%04x-%04x-%012llx}", static_cast<unsigned>(a >> 32),
                static_cast<unsigned>((a >> 16) & 0xffff), static_cast<unsigned>(a & 0xffff),
                static_cast<unsigned>(b >> 48),
                static_cast<unsigned long long>(b & 0xffffffffffffull));
  return buf;
}

}  // namespace

FmuLayout MakeLayout(const CompiledModel& model, const std::vector<double>& parameter_values) {
  const FlatSystem& flat = *model.flat;
  FmuLayout layout;
  auto add = [&layout](FmuVariable v) {
    v.value_reference = static_cast<uint32_t>(layout.variables.size());
    layout.variables.push_back(std::move(v));
    return layout.variables.back().value_reference;
  };
  for (size_t k = 0; k < flat.parameters.size(); ++k) {
    const ParamId p(static_cast<uint32_t>(k));
    FmuVariable v;
    v.name = flat.ParameterName(p);
    v.unit = flat.ParameterUnit(p);
    v.description = flat.ParameterDoc(p);
    v.index = k;
    v.start = parameter_values[k];
    v.structural = flat.structural.Find(p) != nullptr;
    add(std::move(v));
  }
  // States by name, to find the outputs that are states.
  std::map<std::string, size_t> state_of;
  for (size_t j = 0; j < model.num_states(); ++j)
    state_of[flat.VariableName(model.unknowns[model.state_y[j]])] = j;
  layout.state_refs.assign(model.num_states(), UINT32_MAX);
  const std::vector<std::string> units = OutputUnits(flat, model.output_names);
  for (size_t k = 0; k < model.output_names.size(); ++k) {
    FmuVariable v;
    v.name = model.output_names[k];
    v.unit = units[k];
    v.kind = VariableKind::kOutput;
    v.index = k;
    if (auto it = state_of.find(v.name);
        it != state_of.end() && layout.state_refs[it->second] == UINT32_MAX) {
      v.state = static_cast<int>(it->second);
      layout.state_refs[it->second] = add(std::move(v));
      continue;
    }
    add(std::move(v));
  }
  for (size_t j = 0; j < model.num_states(); ++j) {
    if (layout.state_refs[j] != UINT32_MAX) continue;
    const VarId id = model.unknowns[model.state_y[j]];
    FmuVariable v;
    v.name = flat.VariableName(id);
    v.unit = flat.VariableUnit(id);
    v.kind = VariableKind::kState;
    v.index = j;
    v.state = static_cast<int>(j);
    layout.state_refs[j] = add(std::move(v));
  }
  for (size_t j = 0; j < model.num_states(); ++j) {
    FmuVariable v;
    v.name = "der(" + layout.variables[layout.state_refs[j]].name + ")";
    v.kind = VariableKind::kDerivative;
    v.index = j;
    v.state = static_cast<int>(j);
    layout.derivative_refs.push_back(add(std::move(v)));
  }
  layout.num_event_indicators = model.conditions.size() + model.impacts.size();
  // The GUID: everything above but the values.
  std::string text = "momenta-fmu 1\n" + flat.model_name + "\n";
  for (const FmuVariable& v : layout.variables) {
    text += std::to_string(static_cast<int>(v.kind)) + " " + std::to_string(v.value_reference) +
            " " + v.name + " [" + v.unit + "] " + std::to_string(v.state) +
            (v.structural ? " structural\n" : "\n");
  }
  text += "indicators " + std::to_string(layout.num_event_indicators) + "\n";
  layout.guid = GuidOf(text);
  return layout;
}

std::string ModelIdentifier(const std::string& model_name) {
  std::string id;
  for (char c : model_name) id += std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
  if (id.empty() || std::isdigit(static_cast<unsigned char>(id[0]))) id = "m_" + id;
  return id;
}

}  // namespace momenta::fmu
