#pragma once
/// The types of a library file, of a model's `define:` section and of a `uses:` file as the loader
/// reads them (docs/FORMAT.md): connector types and component types, in the vocabulary of
/// core/lang/yaml_loader_values.h.

#include <string>
#include <vector>

#include "core/lang/component_type.h"
#include "core/lang/yaml_loader_values.h"

namespace momenta {

/// Connector type `name`: a signal (`causality:` input or output, with a `type:`) or physical
/// connector (as many `flow:` as `potential:` variables).
ConnectorType ReadConnectorType(const ValueReader& reader, const std::string& name,
                                const YamlNode& n);

/// Component type `name`: its declarations, parts and connections; `user` for a type of the
/// model's own (define: or uses:), not the library's.
ComponentType ReadComponentType(const ValueReader& reader, const std::string& name,
                                const YamlNode& n, bool user);

/// The types of the mapping `root` (name: {kind: …}): connector types go to `library` (in their
/// scalar form), component types to `defines` when it is given, else to `library`. With `user`
/// (a model's define: section, a uses: file) only component types may appear. `what` names the
/// mapping in messages (default: "define" or "a library file").
void ReadLibraryEntries(const ValueReader& reader, const YamlNode& root, Library* library,
                        std::vector<ComponentType>* defines, bool user, const char* what = nullptr);

}  // namespace momenta
