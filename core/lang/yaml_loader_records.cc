// Reading records, expression functions and connection-graph declarations
// (core/lang/yaml_loader_records.h).

#include "core/lang/yaml_loader_records.h"

#include "core/lang/parser.h"

namespace momenta {

RecordType ReadRecordType(const ValueReader& reader, const std::string& name, const YamlNode& n) {
  RecordType r;
  r.name = name;
  r.loc = reader.Loc(n);
  reader.CheckKeys(n, "record type " + name, {"kind", "doc", "fields", "overdetermined"});
  if (n["doc"]) r.doc = reader.Scalar(n["doc"], name + ".doc");
  if (!n["fields"]) reader.Fail(n, "record type " + name + " needs fields:");
  reader.ExpectMap(n["fields"], "fields of " + name);
  for (auto it = n["fields"].begin(); it != n["fields"].end(); ++it) {
    ConnectorVariable f;
    f.name = reader.Name(it->first, "field of " + name);
    if (it->second.IsMap()) {
      reader.CheckKeys(it->second, name + "." + f.name, {"unit", "doc", "shape"});
      if (it->second["shape"]) f.shape = reader.ReadShape(it->second["shape"], name + "." + f.name);
      if (it->second["unit"]) f.unit = reader.UnitString(it->second["unit"], name + "." + f.name);
      if (it->second["doc"]) f.doc = it->second["doc"].Scalar();
    }
    r.fields.push_back(std::move(f));
  }
  if (n["overdetermined"]) {
    reader.ExpectMap(n["overdetermined"], "overdetermined of " + name);
    reader.CheckKeys(n["overdetermined"], "overdetermined of " + name, {"residues"});
    if (!n["overdetermined"]["residues"]) reader.Fail(n["overdetermined"], "overdetermined of " + name + " needs residues:");
    const double k = reader.Number(n["overdetermined"]["residues"], name + ".residues");
    if (!(k >= 1 && k <= 64) || k != static_cast<int>(k)) {
      reader.Fail(n["overdetermined"]["residues"], "the residues of " + name + " must be a whole number from 1 to 64");
    }
    r.residues = static_cast<int>(k);
  }
  return r;
}

FunctionDecl ReadFunction(const ValueReader& reader, const std::string& name, const YamlNode& n) {
  FunctionDecl f;
  f.name = name;
  f.loc = reader.Loc(n);
  reader.CheckKeys(n, "function " + name, {"kind", "doc", "inputs", "value", "returns"});
  if (n["doc"]) f.doc = reader.Scalar(n["doc"], name + ".doc");
  if (n["inputs"] && !n["inputs"].IsNull()) {
    reader.ExpectMap(n["inputs"], "inputs of " + name);
    for (auto it = n["inputs"].begin(); it != n["inputs"].end(); ++it) {
      FunctionDecl::Input in;
      in.name = reader.Name(it->first, "input of " + name);
      if (it->second.IsSequence()) {
        if (it->second.size() > 0) in.shape = reader.ReadShape(it->second, name + "." + in.name);
      } else {
        const std::string t = reader.Scalar(it->second, "type of input " + name + "." + in.name);
        if (t != "Real") in.record = t;
      }
      f.inputs.push_back(std::move(in));
    }
  }
  if (!n["value"]) reader.Fail(n, "function " + name + " needs value:");
  if (n["value"].IsMap()) {
    if (!n["returns"]) reader.Fail(n, "function " + name + " returns a record: name it with returns:");
    f.record = reader.Name(n["returns"], "returns of " + name);
    for (auto it = n["value"].begin(); it != n["value"].end(); ++it) {
      const std::string field = reader.Name(it->first, "field of the value of " + name);
      const std::string text = reader.Scalar(it->second, name + ".value." + field);
      f.fields.emplace_back(field, ParseExpression(text, reader.TextLoc(it->second)));
      f.field_texts.push_back(text);
    }
  } else {
    f.value_text = reader.Scalar(n["value"], name + ".value");
    f.value = ParseExpression(f.value_text, reader.TextLoc(n["value"]));
  }
  RegisterFunction(name, static_cast<int>(f.inputs.size()));
  return f;
}

namespace {

/// One item of a graph list: a name, or a mapping with `of:`/`between:`, `priority:`, `if:`.
GraphDecl ReadGraphItem(const ValueReader& reader, const YamlNode& item, const std::string& what, bool branch) {
  GraphDecl g;
  g.loc = reader.Loc(item);
  auto pair = [&](const YamlNode& p) {
    if (!p.IsSequence() || p.size() != 2) reader.Fail(p, what + ": a branch names two record potentials, [frame_a.R, frame_b.R]");
    g.a = reader.Scalar(p[0], what);
    g.b = reader.Scalar(p[1], what);
  };
  if (item.IsMap()) {
    reader.CheckKeys(item, what, {"of", "between", "priority", "if"});
    if (branch) {
      if (!item["between"]) reader.Fail(item, what + " needs between: [a, b]");
      pair(item["between"]);
    } else {
      if (!item["of"]) reader.Fail(item, what + " needs of:");
      g.a = reader.Scalar(item["of"], what);
    }
    if (item["priority"]) g.priority = static_cast<int>(reader.Number(item["priority"], what + ".priority"));
    if (item["if"]) g.condition = reader.Scalar(item["if"], what + ".if");
  } else if (branch) {
    pair(item);
  } else {
    g.a = reader.Scalar(item, what);
  }
  return g;
}

}  // namespace

void ReadGraphDecls(const ValueReader& reader, const YamlNode& n, const std::string& name, ComponentType* t) {
  struct List {
    const char* key;
    std::vector<GraphDecl>* out;
    bool branch;
  };
  for (const List& l : {List{"roots", &t->roots, false}, List{"potential_roots", &t->potential_roots, false},
                        List{"branches", &t->branches, true}}) {
    const YamlNode list = n[l.key];
    if (!list || list.IsNull()) continue;
    const std::string what = std::string(l.key) + " of " + name;
    if (list.IsMap() && !l.branch) {  // {frame_a.R: 0}: potential roots with their priorities
      for (auto it = list.begin(); it != list.end(); ++it) {
        GraphDecl g;
        g.loc = reader.Loc(it->second);
        g.a = it->first.as<std::string>();
        g.priority = static_cast<int>(reader.Number(it->second, what + "." + g.a));
        l.out->push_back(std::move(g));
      }
      continue;
    }
    if (!list.IsSequence()) reader.Fail(list, what + " must be a list");
    for (const auto& item : list) l.out->push_back(ReadGraphItem(reader, item, what, l.branch));
  }
}

}  // namespace momenta
