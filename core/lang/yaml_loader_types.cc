// Reading connector and component types (core/lang/yaml_loader_types.h).

#include "core/lang/yaml_loader_types.h"

#include <utility>

#include "core/lang/arrays.h"
#include "core/lang/yaml_loader_declarations.h"
#include "core/lang/yaml_loader_parts.h"

namespace momenta {

namespace {

/// The `potential:` or `flow:` variables (`key`) of connector type `name`.
void ReadConnectorVariables(const ValueReader& in, const std::string& name, const YamlNode& n,
                            const char* key, std::vector<ConnectorVariable>* out) {
  if (!n[key]) return;
  in.ExpectMap(n[key], std::string(key) + " of " + name);
  for (auto it = n[key].begin(); it != n[key].end(); ++it) {
    ConnectorVariable v;
    v.name = it->first.as<std::string>();
    if (it->second.IsMap()) {
      in.CheckKeys(it->second, name + "." + v.name, {"unit", "doc", "shape"});
      if (it->second["shape"]) v.shape = in.ReadShape(it->second["shape"], name + "." + v.name);
      if (it->second["unit"]) v.unit = in.UnitString(it->second["unit"], name + "." + v.name);
      if (it->second["doc"]) v.doc = it->second["doc"].Scalar();
    }
    out->push_back(v);
  }
}

/// The `connectors:` of component type `name`: each a type, or a mapping with `type:` and
/// `doc:`, `shape:`, `condition:`.
std::vector<ConnectorDecl> ReadConnectorDecls(const ValueReader& in, const std::string& name,
                                              const YamlNode& connectors) {
  std::vector<ConnectorDecl> out;
  in.ExpectMap(connectors, "connectors of " + name);
  for (auto it = connectors.begin(); it != connectors.end(); ++it) {
    ConnectorDecl c;
    c.name = it->first.as<std::string>();
    c.loc = in.Loc(it->second);
    if (it->second.IsMap()) {
      in.CheckKeys(it->second, "connector " + name + "." + c.name, {"type", "doc", "shape", "condition"});
      if (it->second["shape"]) c.shape = in.ReadShape(it->second["shape"], name + "." + c.name);
      if (!it->second["type"]) in.Fail(it->second, "connector " + name + "." + c.name + " needs a type");
      c.type = in.Scalar(it->second["type"], "type");
      if (it->second["doc"]) c.doc = it->second["doc"].Scalar();
      if (it->second["condition"]) c.condition = in.Name(it->second["condition"], "condition of connector " + name + "." + c.name);
    } else {
      c.type = in.Scalar(it->second, "type of connector " + name + "." + c.name);
    }
    out.push_back(c);
  }
  return out;
}

}  // namespace

ConnectorType ReadConnectorType(const ValueReader& in, const std::string& name, const YamlNode& n) {
  ConnectorType c;
  c.name = name;
  c.loc = in.Loc(n);
  in.CheckKeys(n, "connector type " + name, {"kind", "doc", "potential", "flow", "causality", "type"});
  if (n["doc"]) c.doc = in.Scalar(n["doc"], name + ".doc");
  if (n["causality"]) {
    std::string s = in.Scalar(n["causality"], name + ".causality");
    if (s != "input" && s != "output") {
      in.Fail(n["causality"], "causality of " + name + " must be input or output, found '" + s + "'");
    }
    c.is_signal = true;
    c.is_input = s == "input";
    c.signal_type = n["type"] ? in.Type(n["type"], name) : ValueType::kReal;
    if (n["potential"] || n["flow"]) {
      in.Fail(n, "signal connector " + name + " cannot have potential or flow variables");
    }
    return c;
  }
  ReadConnectorVariables(in, name, n, "potential", &c.potentials);
  ReadConnectorVariables(in, name, n, "flow", &c.flows);
  if (c.potentials.size() != c.flows.size()) {
    in.Fail(n, "connector type " + name + " must have as many flow as potential variables");
  }
  return c;
}

ComponentType ReadComponentType(const ValueReader& in, const std::string& name, const YamlNode& n,
                                bool user) {
  ComponentType t;
  t.name = name;
  t.loc = in.Loc(n);
  t.user_defined = user;
  in.ExpectMap(n, "component type " + name);
  in.CheckKeys(n, "component type " + name,
               {"kind", "doc", "parameters", "connectors", "variables", "equations",
                "initial_equations", "when", "impact", "animation", "components", "connections"});
  if (n["doc"]) t.doc = in.Scalar(n["doc"], name + ".doc");
  if (n["parameters"] && !n["parameters"].IsNull()) {
    in.ExpectMap(n["parameters"], "parameters of " + name);
    for (auto it = n["parameters"].begin(); it != n["parameters"].end(); ++it) {
      ParameterDecl p = ReadParameter(in, in.Name(it->first, "parameter of " + name), it->second, name);
      // A size from the value (shape: [":", 2]) makes a table (docs/FORMAT.md, "Tables").
      (IsOpen(p.shape) ? t.tables : t.parameters).push_back(std::move(p));
    }
  }
  if (n["connectors"] && !n["connectors"].IsNull()) t.connectors = ReadConnectorDecls(in, name, n["connectors"]);
  if (n["variables"] && !n["variables"].IsNull()) {
    in.ExpectMap(n["variables"], "variables of " + name);
    for (auto it = n["variables"].begin(); it != n["variables"].end(); ++it) {
      t.variables.push_back(ReadVariable(in, in.Name(it->first, "variable of " + name), it->second, name));
    }
  }
  if (n["equations"]) t.equations = ReadEquations(in, n["equations"], "equations of " + name);
  if (n["initial_equations"]) {
    t.initial_equations = ReadEquations(in, n["initial_equations"], "initial equations of " + name);
  }
  if (n["when"]) t.whens = ReadWhens(in, n["when"], name);
  if (n["impact"]) t.impacts.push_back(ReadImpact(in, n["impact"], name));
  if (n["animation"]) t.animation = ReadAnimation(in, n["animation"], name);
  ReadParts(in, n, &t.components, &t.connections);
  return t;
}

void ReadLibraryEntries(const ValueReader& in, const YamlNode& root, Library* library,
                        std::vector<ComponentType>* defines, bool user, const char* what) {
  in.ExpectMap(root, what ? what : user ? "define" : "a library file");
  for (auto it = root.begin(); it != root.end(); ++it) {
    std::string name = it->first.as<std::string>();
    const YamlNode n = it->second;  // a copy: it->second is a temporary
    in.ExpectMap(n, "type " + name);
    std::string kind = n["kind"] ? in.Scalar(n["kind"], name + ".kind") : "component";
    if (kind == "connector") {
      if (user) in.Fail(n["kind"], "a model's define: section and a uses: file hold component types only; connector types come from the library");
      library->AddConnector(ScalarForm(ReadConnectorType(in, name, n)));
    } else if (kind == "component") {
      ComponentType t = ReadComponentType(in, name, n, user);
      if (defines) {
        defines->push_back(std::move(t));
      } else {
        library->AddComponent(std::move(t));
      }
    } else {
      in.Fail(n["kind"], "unknown kind '" + kind + "' of " + name + " (valid kinds: component, connector)");
    }
  }
}

}  // namespace momenta
