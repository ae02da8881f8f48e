#pragma once
/// A component type (a function, the records and connectors) as bytes and back: the library's types are parsed when the binary is built
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
/// not write (cut short, or with a count past their end); so do the readers below.
ComponentType DeserializeComponentType(std::string_view bytes);

/// A library function as bytes and back.
std::string SerializeFunction(const FunctionDecl& function);
FunctionDecl DeserializeFunction(std::string_view bytes);

/// The records and connector types of `library` (its own, none it reads lazily) as bytes, and
/// back into another library.
std::string SerializeRecordsAndConnectors(const Library& library);
void DeserializeRecordsAndConnectors(std::string_view bytes, Library* library);

}  // namespace momenta
