#pragma once
/// What the 3-D library's language adds to a library file (docs/FORMAT.md, "Records, functions
/// and the connection graph"): record types, expression functions, and a component type's
/// connection-graph declarations (roots, potential roots, branches).

#include <string>

#include "core/lang/component_type.h"
#include "core/lang/yaml_loader_values.h"

namespace momenta {

/// `kind: record`: `fields:` (each with `shape`, `unit`, `doc`) and `overdetermined: {residues: n}`.
RecordType ReadRecordType(const ValueReader& reader, const std::string& name, const YamlNode& n);

/// `kind: function`: `inputs:` (name → a shape list, or a record type's name) and `value:` (an
/// expression, or a mapping field → expression for a record value, with `returns:` the record).
/// Registers the name with the parser (RegisterFunction).
FunctionDecl ReadFunction(const ValueReader& reader, const std::string& name, const YamlNode& n);

/// `roots:`, `potential_roots:` and `branches:` of component type `name` into `t`.
void ReadGraphDecls(const ValueReader& reader, const YamlNode& n, const std::string& name, ComponentType* t);

}  // namespace momenta
