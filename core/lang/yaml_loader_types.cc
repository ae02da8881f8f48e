// Reading connector and component types (core/lang/yaml_loader_types.h).

#include "core/lang/yaml_loader_types.h"

#include <utility>

#include "core/lang/arrays.h"
#include "core/lang/yaml_loader_declarations.h"
#include "core/lang/yaml_loader_parts.h"
#include "core/lang/yaml_loader_records.h"
#include "core/lang/parser.h"
#include "core/lang/records.h"

namespace momenta {

namespace {

/// The `potential:` or `flow:` variables (`key`) of connector type `name`.
void ReadConnectorVariables(const ValueReader& reader, const std::string& name, const YamlNode& n,
                            const char* key, std::vector<ConnectorVariable>* out) {
  if (!n[key]) return;
  reader.ExpectMap(n[key], std::string(key) + " of " + name);
  for (auto it = n[key].begin(); it != n[key].end(); ++it) {
    ConnectorVariable v;
    v.name = it->first.as<std::string>();
    if (it->second.IsMap()) {
      reader.CheckKeys(it->second, name + "." + v.name, {"unit", "doc", "shape", "type"});
      if (it->second["type"]) {
        if (std::string(key) != "potential") reader.Fail(it->second["type"], "only a potential of " + name + " may be a record");
        v.record = reader.Name(it->second["type"], "type of " + name + "." + v.name);
      }
      if (it->second["shape"]) v.shape = reader.ReadShape(it->second["shape"], name + "." + v.name);
      if (it->second["unit"]) v.unit = reader.UnitString(it->second["unit"], name + "." + v.name);
      if (it->second["doc"]) v.doc = it->second["doc"].Scalar();
    }
    out->push_back(v);
  }
}

/// The `connectors:` of component type `name`: each a type, or a mapping with `type:` and
/// `doc:`, `shape:`, `condition:`.
std::vector<ConnectorDecl> ReadConnectorDecls(const ValueReader& reader, const std::string& name,
                                              const YamlNode& connectors) {
  std::vector<ConnectorDecl> out;
  reader.ExpectMap(connectors, "connectors of " + name);
  for (auto it = connectors.begin(); it != connectors.end(); ++it) {
    ConnectorDecl c;
    c.name = it->first.as<std::string>();
    c.loc = reader.Loc(it->second);
    if (it->second.IsMap()) {
      reader.CheckKeys(it->second, "connector " + name + "." + c.name,
                       {"type", "doc", "shape", "condition"});
      if (it->second["shape"]) c.shape = reader.ReadShape(it->second["shape"], name + "." + c.name);
      if (!it->second["type"])
        reader.Fail(it->second, "connector " + name + "." + c.name + " needs a type");
      c.type = reader.Scalar(it->second["type"], "type");
      if (it->second["doc"]) c.doc = it->second["doc"].Scalar();
      if (it->second["condition"])
        c.condition =
            reader.Name(it->second["condition"], "condition of connector " + name + "." + c.name);
    } else {
      c.type = reader.Scalar(it->second, "type of connector " + name + "." + c.name);
    }
    out.push_back(c);
  }
  return out;
}

}  // namespace

ConnectorType ReadConnectorType(const ValueReader& reader, const std::string& name,
                                const YamlNode& n) {
  ConnectorType c;
  c.name = name;
  c.loc = reader.Loc(n);
  reader.CheckKeys(n, "connector type " + name,
                   {"kind", "doc", "potential", "flow", "causality", "type"});
  if (n["doc"]) c.doc = reader.Scalar(n["doc"], name + ".doc");
  if (n["causality"]) {
    std::string s = reader.Scalar(n["causality"], name + ".causality");
    if (s != "input" && s != "output") {
      reader.Fail(n["causality"],
                  "causality of " + name + " must be input or output, found '" + s + "'");
    }
    c.is_signal = true;
    c.is_input = s == "input";
    c.signal_type = n["type"] ? reader.Type(n["type"], name) : ValueType::kReal;
    if (n["potential"] || n["flow"]) {
      reader.Fail(n, "signal connector " + name + " cannot have potential or flow variables");
    }
    return c;
  }
  ReadConnectorVariables(reader, name, n, "potential", &c.potentials);
  ReadConnectorVariables(reader, name, n, "flow", &c.flows);
  if (c.potentials.size() != c.flows.size()) {
    reader.Fail(n, "connector type " + name + " must have as many flow as potential variables");
  }
  return c;
}

ComponentType ReadComponentType(const ValueReader& reader, const std::string& name,
                                const YamlNode& n, bool user) {
  ComponentType t;
  t.name = name;
  t.loc = reader.Loc(n);
  t.user_defined = user;
  reader.ExpectMap(n, "component type " + name);
  reader.CheckKeys(
      n, "component type " + name,
      {"kind", "doc", "parameters", "connectors", "variables", "equations", "initial_equations",
       "when", "impact", "animation", "components", "connections", "roots", "potential_roots",
       "branches", "outer"});
  if (n["doc"]) t.doc = reader.Scalar(n["doc"], name + ".doc");
  if (n["parameters"] && !n["parameters"].IsNull()) {
    reader.ExpectMap(n["parameters"], "parameters of " + name);
    for (auto it = n["parameters"].begin(); it != n["parameters"].end(); ++it) {
      ParameterDecl p =
          ReadParameter(reader, reader.Name(it->first, "parameter of " + name), it->second, name);
      // A size from the value (shape: [":", 2]) makes a table (docs/FORMAT.md, "Tables").
      (IsOpen(p.shape) ? t.tables : t.parameters).push_back(std::move(p));
    }
  }
  if (n["connectors"] && !n["connectors"].IsNull())
    t.connectors = ReadConnectorDecls(reader, name, n["connectors"]);
  if (n["variables"] && !n["variables"].IsNull()) {
    reader.ExpectMap(n["variables"], "variables of " + name);
    for (auto it = n["variables"].begin(); it != n["variables"].end(); ++it) {
      t.variables.push_back(
          ReadVariable(reader, reader.Name(it->first, "variable of " + name), it->second, name));
    }
  }
  if (n["equations"]) t.equations = ReadEquations(reader, n["equations"], "equations of " + name, &t.blocks);
  if (n["initial_equations"]) {
    t.initial_equations =
        ReadEquations(reader, n["initial_equations"], "initial equations of " + name, &t.blocks);
  }
  ReadGraphDecls(reader, n, name, &t);
  if (n["outer"] && !n["outer"].IsNull()) {
    reader.ExpectMap(n["outer"], "outer of " + name);
    for (auto it = n["outer"].begin(); it != n["outer"].end(); ++it) {
      t.outers[reader.Name(it->first, "outer of " + name)] = reader.Scalar(it->second, "type of an outer of " + name);
    }
  }
  if (n["when"]) t.whens = ReadWhens(reader, n["when"], name);
  if (n["impact"]) t.impacts.push_back(ReadImpact(reader, n["impact"], name));
  if (n["animation"]) t.animation = ReadAnimation(reader, n["animation"], name);
  ReadParts(reader, n, &t.components, &t.connections);
  return t;
}

void ReadLibraryEntries(const ValueReader& reader, const YamlNode& root, Library* library,
                        std::vector<ComponentType>* defines, bool user, const char* what) {
  reader.ExpectMap(root, what ? what : user ? "define" : "a library file");
  // Every function's name first, so that a function may call one declared after it.
  for (auto it = root.begin(); it != root.end(); ++it) {
    const YamlNode n = it->second;
    if (n.IsMap() && n["kind"] && n["kind"].IsScalar() && n["kind"].Scalar() == "function") {
      RegisterFunction(it->first.as<std::string>(), -1);
    }
  }
  for (auto it = root.begin(); it != root.end(); ++it) {
    std::string name = it->first.as<std::string>();
    const YamlNode n = it->second;  // a copy: it->second is a temporary
    reader.ExpectMap(n, "type " + name);
    std::string kind = n["kind"] ? reader.Scalar(n["kind"], name + ".kind") : "component";
    if (kind == "connector") {
      // A model's own connector is expanded when the model is flattened, over the library.
      ConnectorType c = ReadConnectorType(reader, name, n);
      library->AddConnector(user ? std::move(c) : ScalarForm(ExpandRecords(std::move(c), *library)));
    } else if (kind == "record") {
      library->AddRecord(ReadRecordType(reader, name, n));
    } else if (kind == "function") {
      library->AddFunction(ReadFunction(reader, name, n));
    } else if (kind == "component") {
      ComponentType t = ReadComponentType(reader, name, n, user);
      if (defines) {
        defines->push_back(std::move(t));
      } else {
        library->AddComponent(std::move(t));
      }
    } else {
      reader.Fail(n["kind"], "unknown kind '" + kind + "' of " + name +
                                 " (valid kinds: component, connector, record, function)");
    }
  }
}

}  // namespace momenta
