// `momenta list [NAME]`: the component library by file, or one component (its parameters, tables,
// connectors, variables and equations) or connector type.

#include <algorithm>
#include <iostream>
#include <map>

#include "app/commands.h"
#include "app/csv_writer.h"
#include "core/lang/builtin_library.h"

namespace momenta {

namespace {

/// Every component of the library under its file's name, with its doc, then the connectors.
void ListLibrary(std::ostream& o, const Library& lib) {
  std::map<std::string, std::vector<const ComponentType*>> by_file;
  for (const auto& n : lib.ComponentNames()) {
    const ComponentType* t = lib.FindComponent(n);
    by_file[t->loc.file()].push_back(t);
  }
  size_t width = 0;  // the names in one column, two spaces after the longest
  for (const auto& n : lib.ComponentNames()) width = std::max(width, n.size());
  for (const auto& [file, types] : by_file) {
    o << file << "\n";
    for (const ComponentType* t : types) {
      o << "  " << t->name << std::string(width + 2 - t->name.size(), ' ') << t->doc << "\n";
    }
  }
  o << "connectors: " << JoinNames(lib.ConnectorNames()) << "\n";
}

void DescribeConnector(std::ostream& o, const ConnectorType& c) {
  o << c.name << " (connector): " << c.doc << "\n";
  for (const auto& v : c.potentials) o << "  potential " << v.name << " [" << v.unit << "]: " << v.doc << "\n";
  for (const auto& v : c.flows) o << "  flow " << v.name << " [" << v.unit << "]: " << v.doc << "\n";
  if (c.is_signal) {
    o << "  signal " << (c.is_input ? "input" : "output") << " of type " << ValueTypeName(c.signal_type) << "\n";
  }
}

void DescribeComponent(std::ostream& o, const ComponentType& t) {
  o << t.name << ": " << t.doc << "\n";
  if (!t.parameters.empty()) o << "parameters:\n";
  for (const auto& p : t.parameters) {
    o << "  " << p.name << " = " << p.value_text << (p.unit.empty() ? "" : " [" + p.unit + "]");
    if (p.min) o << ", min " << FormatDouble(*p.min);
    if (p.max) o << ", max " << FormatDouble(*p.max);
    o << (p.doc.empty() ? "" : ": " + p.doc) << "\n";
  }
  if (!t.tables.empty()) o << "tables (sized by their value):\n";
  for (const auto& p : t.tables) {
    o << "  " << p.name << " = " << p.value_text << (p.unit.empty() ? "" : " [" + p.unit + "]")
      << (p.doc.empty() ? "" : ": " + p.doc) << "\n";
  }
  if (!t.connectors.empty()) o << "connectors:\n";
  for (const auto& c : t.connectors) {
    o << "  " << c.name << ": " << c.type << (c.condition.empty() ? "" : " if " + c.condition)
      << (c.doc.empty() ? "" : " — " + c.doc) << "\n";
  }
  if (!t.variables.empty()) o << "variables:\n";
  for (const auto& v : t.variables) {
    o << "  " << v.name << (v.unit.empty() ? "" : " [" + v.unit + "]") << (v.doc.empty() ? "" : ": " + v.doc) << "\n";
  }
  o << "equations:\n";
  for (const auto& e : t.equations) o << "  " << e.text << "\n";
  for (const auto& e : t.initial_equations) o << "  initial: " << e.text << "\n";
}

}  // namespace

int RunList(const std::string& name) {
  const Library& lib = BuiltinLibrary();
  if (name.empty()) {
    ListLibrary(std::cout, lib);
    return kExitOk;
  }
  if (const ComponentType* t = lib.FindComponent(name)) {
    DescribeComponent(std::cout, *t);
    return kExitOk;
  }
  if (const ConnectorType* c = lib.FindConnector(name)) {
    DescribeConnector(std::cout, *c);
    return kExitOk;
  }
  auto close = ClosestNames(name, lib.ComponentNames());
  std::cerr << "momenta: no component named '" << name << "'"
            << (close.empty() ? "" : " (did you mean " + JoinNames(close) + "?)") << " (valid: "
            << JoinNames(lib.ComponentNames(), 200) << ")\n";
  return kExitUsage;
}

}  // namespace momenta
