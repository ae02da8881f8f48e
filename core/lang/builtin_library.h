#pragma once
/// The component library compiled into the binary (components/*.yaml, embedded at build time).

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "core/lang/component_type.h"

namespace momenta {

/// The library compiled into the binary (components/*.yaml).
const Library& BuiltinLibrary();

/// The library as the build parsed it (core/lang/compiled_types.h): entry k of the embedded
/// library's table (builtin_library_data.inc), a component type or a function, is bytes
/// [offsets[k], offsets[k + 1]) of `bytes` (core/lang/type_serial.h), none where the two are
/// equal (records and connector types); one range more holds the records and connector types the
/// library starts with.
struct CompiledLibraryTypes {
  uint64_t library_hash = 0;  ///< of the library text they were parsed from
  const char* bytes = nullptr;
  const uint32_t* offsets = nullptr;
  size_t entries = 0;  ///< ranges: the entries and the start
};

/// From now on BuiltinLibrary reads its records, connector types, component types and functions
/// from `types` instead of parsing their text, when they were compiled from this binary's library
/// text (the hash and the number of entries agree; otherwise they are not used, and false is
/// returned). Call it before the first BuiltinLibrary().
bool UseCompiledLibraryTypes(const CompiledLibraryTypes& types);

/// Every record, connector type, component type (in its scalar form) and function of the library
/// parsed from its text and serialised: what CompiledLibraryTypes points to, which the build-time
/// tool momenta_compile_types writes as C++ tables (core/lang/compile_types_tool.cc).
struct SerializedLibrary {
  uint64_t library_hash = 0;  ///< of the library text
  std::string bytes;
  std::vector<uint32_t> offsets;
  std::vector<char> kinds;  ///< by entry: 't' a component type, 'f' a function, 'r' a record, 'k' a connector type
};
SerializedLibrary SerializeLibrary();

}  // namespace momenta
