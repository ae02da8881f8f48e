#pragma once
/// A component type as bytes and back: the library's types are parsed when the binary is built
/// and stored in this form (core/lang/compiled_types.cc), so that a run reads the few it uses
/// without parsing their YAML and equations again (bench/RESULTS.md, "Read this first").
///
/// The bytes hold every field of ComponentType and of what it holds; its expression trees keep
/// their sharing (a subtree two fields point to is stored once). They are read only by the binary
/// that wrote them (same build, same library text: BuiltinLibrary checks the library's hash).

#include <string>
#include <string_view>

#include "core/lang/component_type.h"

namespace momenta {

/// `type` as bytes.
std::string SerializeComponentType(const ComponentType& type);

/// The type SerializeComponentType wrote into `bytes`. Throws std::runtime_error on bytes it did
/// not write (cut short, or with a count past their end).
ComponentType DeserializeComponentType(std::string_view bytes);

}  // namespace momenta
