// The flat system's names and texts, made on demand from the records' references (TextRef).

#include <string_view>

#include "core/flat_system.h"

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
  return f.instances[r.a].path + "." + Held(f, r, table);
}

/// Whether `r` names `name` (compared in place: a lookup makes no string).
bool NameIs(const FlatSystem& f, const TextRef& r, NameTable table, std::string_view name) {
  if (r.kind != TextRef::kType) return Held(f, r, table) == name;
  const std::string& path = f.instances[r.a].path;
  return name.size() > path.size() && name.compare(0, path.size(), path) == 0 && name[path.size()] == '.' &&
         name.substr(path.size() + 1) == Held(f, r, table);
}

}  // namespace

TextRef FlatSystem::Own(std::string text) {
  if (text.empty()) return {};
  texts.push_back(std::move(text));
  return {TextRef::kOwned, static_cast<uint32_t>(texts.size() - 1), 0};
}

std::string FlatSystem::VariableName(VarId v) const { return Name(*this, variables[v.value()].name, &TypeNames::vars); }

const std::string& FlatSystem::VariableUnit(VarId v) const {
  return Held(*this, variables[v.value()].unit, &TypeNames::var_units);
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
      return WithPath(Held(*this, r, &TypeNames::equations), instances[r.a].path);
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
    s = inst.path + " (" + inst.type->name + ", " + inst.loc.ToString() + "): " + quoted;
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

}  // namespace momenta
