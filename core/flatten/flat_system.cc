// The flat system's names and texts, made on demand from the records' references (TextRef).

#include "core/flatten/flat_system.h"

#include <string_view>
#include <unordered_map>

namespace momenta {

namespace {

const std::string kNoText;

/// A type's equation text with its placeholders ('\x01': a connector relative to the instance)
/// replaced by the instance's path.
std::string WithPath(const std::string& text, const std::string& path) {
  if (text.find('\x01') == std::string::npos) return text;
  std::string r;
  for (char ch : text) {
    if (ch == '\x01') {
      r += path;
      r += '.';
    } else {
      r += ch;
    }
  }
  return r;
}

using NameTable = std::vector<std::string> TypeNames::*;

/// What `r` names without an instance's path: the held text, or the entry of the instance's
/// type's `table` (a local name, a unit, a doc).
const std::string& Held(const FlatSystem& f, const TextRef& r, NameTable table) {
  switch (r.kind) {
    case TextRef::kOwned: return f.texts[r.a];
    case TextRef::kType: return (*f.type_names[f.instances[r.a].names].*table)[r.b];
    default: return kNoText;
  }
}

/// A full name: the held name, or the instance's path, a dot and the local name from `table`.
std::string Name(const FlatSystem& f, const TextRef& r, NameTable table) {
  if (r.kind != TextRef::kType) return Held(f, r, table);
  return f.InstancePath(InstanceId(r.a)) + "." + Held(f, r, table);
}

/// Whether `r` names `name` (compared in place: a lookup makes no string).
bool NameIs(const FlatSystem& f, const TextRef& r, NameTable table, std::string_view name) {
  if (r.kind != TextRef::kType) return Held(f, r, table) == name;
  size_t length = 0;
  return f.StartsWithPath(InstanceId(r.a), name, &length) && name.size() > length && name[length] == '.' &&
         name.substr(length + 1) == Held(f, r, table);
}

/// An element's index as written in its path: "12" in R[12].
std::string IndexText(uint32_t element) { return std::to_string(element + 1); }

}  // namespace

TextRef FlatSystem::Own(std::string text) {
  if (text.empty()) return {};
  texts.push_back(std::move(text));
  return {TextRef::kOwned, static_cast<uint32_t>(texts.size() - 1), 0};
}

std::string FlatSystem::InstancePath(InstanceId i) const {
  const FlatInstance& inst = instances[i.value()];
  if (inst.block < 0) return texts[inst.path_text];
  const FlatBlock& b = blocks[inst.block];
  const uint32_t offset = i.value() - b.first_instance.value();
  std::string path = b.name + "[" + IndexText(offset / b.stride) + "]";
  if (offset % b.stride != 0) path += "." + b.part_paths[offset % b.stride - 1];
  return path;
}

bool FlatSystem::StartsWithPath(InstanceId i, std::string_view text, size_t* length) const {
  const FlatInstance& inst = instances[i.value()];
  if (inst.block < 0) {
    const std::string& path = texts[inst.path_text];
    *length = path.size();
    return text.substr(0, path.size()) == path;
  }
  // name[index] or name[index].part
  const FlatBlock& b = blocks[inst.block];
  const uint32_t offset = i.value() - b.first_instance.value();
  const std::string index = IndexText(offset / b.stride);
  size_t at = b.name.size();
  if (text.substr(0, at) != b.name || text.substr(at, 1) != "[" || text.substr(at + 1, index.size()) != index ||
      text.substr(at + 1 + index.size(), 1) != "]") {
    return false;
  }
  at += index.size() + 2;
  if (offset % b.stride != 0) {
    const std::string& part = b.part_paths[offset % b.stride - 1];
    if (text.substr(at, 1) != "." || text.substr(at + 1, part.size()) != part) return false;
    at += 1 + part.size();
  }
  *length = at;
  return true;
}

std::string FlatSystem::VariableName(VarId v) const { return Name(*this, variables[v.value()].name, &TypeNames::vars); }

const std::string& FlatSystem::VariableUnit(VarId v) const {
  const TextRef& name = variables[v.value()].name;
  if (name.kind == TextRef::kType) return Held(*this, name, &TypeNames::var_units);
  if (v.value() < model_variable_units.size()) return Held(*this, model_variable_units[v.value()], &TypeNames::var_units);
  return kNoText;
}

std::string FlatSystem::ParameterName(ParamId p) const {
  return Name(*this, parameters[p.value()].name, &TypeNames::params);
}

const std::string& FlatSystem::ParameterUnit(ParamId p) const {
  return Held(*this, parameters[p.value()].unit, &TypeNames::param_units);
}

const std::string& FlatSystem::ParameterDoc(ParamId p) const {
  return Held(*this, parameters[p.value()].doc, &TypeNames::param_docs);
}

std::string FlatSystem::EquationText(const FlatEquation& eq) const {
  const TextRef& r = eq.text;
  switch (r.kind) {
    case TextRef::kType:
      return WithPath(Held(*this, r, &TypeNames::equations), InstancePath(InstanceId(r.a)));
    case TextRef::kEqual:
      return VariableName(VarId(r.a)) + " = " + VariableName(VarId(r.b)) + " (connection)";
    case TextRef::kUnconnected:
      return VariableName(VarId(r.a)) + " = 0 (unconnected)";
    case TextRef::kFlowSum: {
      // The members' flow variables are named <connector>.<flow>.
      std::string members, flow;
      for (uint32_t k = 0; k < r.b; ++k) {
        const std::string name = VariableName(connection_vars[r.a + k]);
        const size_t dot = name.rfind('.');
        members += (k ? ", " : "") + name.substr(0, dot);
        flow = name.substr(dot + 1);
      }
      return "sum of " + flow + " over {" + members + "} = 0 (connection)";
    }
    default:
      return Held(*this, r, &TypeNames::equations);
  }
}

std::string FlatSystem::WhenText(const FlatWhen& w) const { return Held(*this, w.text, &TypeNames::whens); }

std::optional<ParamId> FlatSystem::FindParameter(const std::string& name) const {
  for (uint32_t k = 0; k < parameters.size(); ++k) {
    if (NameIs(*this, parameters[k].name, &TypeNames::params, name)) return ParamId(k);
  }
  return std::nullopt;
}

ExprNamer FlatSystem::Namer() const {
  ExprNamer n;
  n.var = [this](uint32_t v) { return VariableName(VarId(v)); };
  n.param = [this](uint32_t p) { return ParameterName(ParamId(p)); };
  return n;
}

std::string FlatSystem::DescribeEquation(const FlatEquation& eq) const {
  std::string quoted = "'";
  quoted += EquationText(eq);
  quoted += "'";
  std::string s;
  if (eq.instance.valid() && eq.origin != EquationOrigin::kUnconnectedFlow) {
    const FlatInstance& inst = instances[eq.instance.value()];
    s = InstancePath(eq.instance) + " (" + inst.type->name + ", " + inst.loc.ToString() + "): " + quoted;
  } else {
    s = quoted;
    if (eq.loc.known()) s += " (" + eq.loc.ToString() + ")";
  }
  if (eq.differentiations == 1) s += ", differentiated once";
  if (eq.differentiations == 2) s += ", differentiated twice";
  if (eq.differentiations > 2) s += ", differentiated " + std::to_string(eq.differentiations) + " times";
  return s;
}

std::string FlatSystem::DescribeVariable(VarId v) const {
  const FlatVariable& var = variables[v.value()];
  std::string s = VariableName(v);
  if (var.instance.valid()) {
    const FlatInstance& inst = instances[var.instance.value()];
    s += " (" + inst.type->name + ", " + inst.loc.ToString() + ")";
  }
  return s;
}

std::vector<std::string> OutputUnits(const FlatSystem& flat,
                                     const std::vector<std::string>& output_names) {
  std::unordered_map<std::string, std::string> unit_of;
  for (const auto& o : flat.outputs) unit_of.emplace(o.text, o.unit);
  if (unit_of.size() < output_names.size()) {  // the default outputs: states, by name
    for (uint32_t v = 0; v < flat.variables.size(); ++v) unit_of.emplace(flat.VariableName(VarId(v)), flat.VariableUnit(VarId(v)));
  }
  std::vector<std::string> units;
  for (const auto& name : output_names) {
    auto it = unit_of.find(name);
    units.push_back(it == unit_of.end() ? std::string() : it->second);
  }
  return units;
}

}  // namespace momenta
