// Reading the components and connections of a model or a composite type
// (core/lang/yaml_loader_parts.h).

#include "core/lang/yaml_loader_parts.h"

#include <string>
#include <string_view>
#include <utility>

#include "core/lang/parser.h"

namespace momenta {

namespace {

/// The attributes a component entry may set on a variable of its type: `start`, `fixed`,
/// `nominal` (positive), `min`, `max` (min <= max) and `stateSelect`.
void ReadVariableAttributes(const ValueReader& reader, const YamlNode& value, const MessageSubject& what,
                            const std::string& name, Modifier* m) {
  reader.CheckKeys(value, what, {"start", "fixed", "nominal", "min", "max", "stateSelect"});
  if (const YamlNode start = value["start"]) {
    m->start = reader.Expression(start, MessageSubject{"start of ", name, ".", m->key});
  }
  if (const YamlNode fixed = value["fixed"]) m->fixed = reader.Bool(fixed, what.Plus(".fixed"));
  if (const YamlNode nominal = value["nominal"]) {
    m->nominal = reader.Number(nominal, what.Plus(".nominal"));
    if (!(*m->nominal > 0)) {
      reader.Fail(nominal, what + ".nominal must be a positive number (the variable's typical magnitude), found " +
                               reader.Scalar(nominal, what.Plus(".nominal")));
    }
  }
  m->min = reader.OptionalNumber(value, "min", what);
  m->max = reader.OptionalNumber(value, "max", what);
  if (m->min && m->max && *m->min > *m->max) {
    reader.Fail(value["max"], what + ".max = " + reader.Scalar(value["max"], what.Plus(".max")) +
                                  " is below its min = " + reader.Scalar(value["min"], what.Plus(".min")));
  }
  if (const YamlNode choice = value["stateSelect"]) m->state_priority = reader.StateSelect(choice, what);
}

/// Component `name`: `type:`, and `doc:`, `count:`, `condition:` and a modifier for each other key (a value,
/// or a mapping of `start:`, `fixed:`, `nominal:`, `min:`, `max:`, `stateSelect:`).
ComponentSpec ReadComponentEntry(const ValueReader& reader, const std::string& name,
                                 const YamlNode& n) {
  ComponentSpec c;
  c.name = name;
  c.loc = reader.Loc(n);
  reader.ExpectMap(n, MessageSubject{"component ", name});
  const YamlNode type = n["type"];
  if (!type) reader.Fail(n, "component " + name + " needs a type, e.g. {type: Mass}");
  c.type = reader.Scalar(type, MessageSubject{"type of ", name});
  c.type_loc = reader.Loc(type);
  c.modifiers.reserve(n.size() - 1);
  for (auto it = n.begin(); it != n.end(); ++it) {
    const std::string_view key = it->first.AsText();
    if (key == "type") continue;
    if (key == "doc") {
      c.doc = reader.Scalar(it->second, MessageSubject{name, ".doc"});
      continue;
    }
    if (key == "count") {
      c.count = reader.Expression(it->second, MessageSubject{"count of ", name});
      continue;
    }
    if (key == "condition") {
      c.condition_text = reader.ValueText(it->second, MessageSubject{"condition of ", name});
      c.condition = reader.Expression(it->second, c.condition_text, MessageSubject{"condition of ", name});
      c.condition_loc = reader.TextLoc(it->second);
      continue;
    }
    // Descriptions for messages, made only when there is one.
    const MessageSubject what{name, ".", key};
    Modifier m;
    m.key = key;
    m.loc = reader.Loc(it->first);
    m.key_loc = m.loc;
    const YamlNode value = it->second;
    if (value.IsMap()) {
      ReadVariableAttributes(reader, value, what, name, &m);
    } else {
      m.value_text = reader.ValueText(value, what);
      m.value = reader.ValueExpression(value, m.value_text, what, &m.value_unit);
      m.loc = reader.TextLoc(value);
    }
    c.modifiers.push_back(std::move(m));
  }
  return c;
}

/// A connection end's text and place, and its tree unless it is a plain dotted name, which
/// reads without an error (ConnectionSpec::EndA makes its tree when it is needed).
AstPtr ReadConnectionEnd(const ValueReader& reader, const YamlNode& n, std::string* text,
                         SourceLoc* loc) {
  *text = reader.ScalarText(n, "a connection end");
  *loc = reader.TextLoc(n);
  return IsPlainName(*text) ? nullptr : ParseName(*text, *loc);
}

/// `for: i in 1:n-1`: the loop of a connection mapping, into `c`.
void ReadConnectionLoop(const ValueReader& reader, const YamlNode& loop, ConnectionSpec* c) {
  std::string spec = reader.Scalar(loop, "for");
  SourceLoc loc = reader.TextLoc(loop);
  c->loop_text = spec;
  c->loop_loc = loc;
  size_t in_at = spec.find(" in ");
  size_t colon = spec.find(':', in_at == std::string::npos ? 0 : in_at);
  if (in_at == std::string::npos || colon == std::string::npos) {
    reader.Fail(loop, "'for' must read like 'i in 1:n-1', found '" + spec + "'");
  }
  c->loop_var = spec.substr(0, in_at);
  while (!c->loop_var.empty() && c->loop_var.back() == ' ') c->loop_var.pop_back();
  while (!c->loop_var.empty() && c->loop_var.front() == ' ') c->loop_var.erase(0, 1);
  c->loop_from = ParseExpression(spec.substr(in_at + 4, colon - in_at - 4),
                                 loc.Shifted(static_cast<int>(in_at + 4)));
  c->loop_to = ParseExpression(spec.substr(colon + 1), loc.Shifted(static_cast<int>(colon + 1)));
}

/// A connection: `[a, b]`, or a mapping `{connect: [a, b], for: …}`.
ConnectionSpec ReadConnection(const ValueReader& reader, const YamlNode& n) {
  ConnectionSpec c;
  c.loc = reader.Loc(n);
  if (n.IsMap()) {
    reader.CheckKeys(n, "a connection", {"for", "connect"});
    if (!n["connect"]) reader.Fail(n, "a connection mapping needs 'connect: [a, b]'");
    if (n["for"]) ReadConnectionLoop(reader, n["for"], &c);
  }
  // (yaml-cpp's Node::operator= writes through to the node, so the pair is bound once.)
  const YamlNode pair = n.IsMap() ? n["connect"] : n;
  if (!pair.IsSequence() || pair.size() != 2) {
    reader.Fail(pair, "a connection is a list of two connectors, e.g. [A.flange_b, B.flange_a]");
  }
  c.a = ReadConnectionEnd(reader, pair[0], &c.a_text, &c.a_loc);
  c.b = ReadConnectionEnd(reader, pair[1], &c.b_text, &c.b_loc);
  return c;
}

}  // namespace

void ReadParts(const ValueReader& reader, const YamlNode& n, std::vector<ComponentSpec>* components,
               std::vector<ConnectionSpec>* connections) {
  // (Reserved: a written-out model has 100 000 entries, which would be moved as the lists grow.)
  if (const YamlNode parts = n["components"]; parts && !parts.IsNull()) {
    reader.ExpectMap(parts, "components");
    components->reserve(components->size() + parts.size());
    for (auto it = parts.begin(); it != parts.end(); ++it) {
      components->push_back(
          ReadComponentEntry(reader, reader.Name(it->first, "component"), it->second));
    }
  }
  if (const YamlNode list = n["connections"]; list && !list.IsNull()) {
    if (!list.IsSequence()) reader.Fail(list, "connections must be a list");
    connections->reserve(connections->size() + list.size());
    for (const auto& c : list) connections->push_back(ReadConnection(reader, c));
  }
}

}  // namespace momenta
