#pragma once
/// The parts of a model or a composite type as the loader reads them (docs/FORMAT.md):
/// `components:`, each a type and its modifiers, and `connections:`, each a pair of ends, perhaps
/// in a `for:` loop. A written-out model holds 100 000 of them, so this is the loader's hot path:
/// a description for a message is put together only when there is a message
/// (core/lang/yaml_loader_values.h, MessageSubject).

#include <vector>

#include "core/lang/component_type.h"
#include "core/lang/yaml_loader_values.h"

namespace momenta {

/// `components:` and `connections:` of `n` (a model's root or a component type), appended to
/// `components` and `connections`.
void ReadParts(const ValueReader& reader, const YamlNode& n, std::vector<ComponentSpec>* components,
               std::vector<ConnectionSpec>* connections);

}  // namespace momenta
