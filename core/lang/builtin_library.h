#pragma once
/// The component library compiled into the binary (components/*.yaml, embedded at build time).

#include <cstddef>
#include <cstdint>
#include <string>

#include "core/lang/component_type.h"

namespace momenta {

/// The library compiled into the binary (components/*.yaml).
const Library& BuiltinLibrary();

/// The library's component types as the build parsed them (core/lang/compiled_types.h): entry k
/// of the embedded library's table (builtin_library_data.inc) is bytes [offsets[k],
/// offsets[k + 1]) of `bytes` (SerializeComponentType's form), none where the two are equal.
struct CompiledLibraryTypes {
  uint64_t library_hash = 0;  ///< of the library text they were parsed from
  const char* bytes = nullptr;
  const uint32_t* offsets = nullptr;
  size_t entries = 0;
};

/// From now on BuiltinLibrary reads a component type from `types` instead of parsing its text,
/// when they were compiled from this binary's library text (the hash and the number of entries
/// agree; otherwise they are not used, and false is returned). Call it before any thread reads
/// the library.
bool UseCompiledLibraryTypes(const CompiledLibraryTypes& types);

/// Every component type of the library parsed from its text (in its scalar form) and serialised,
/// as the C++ text of the tables CompiledLibraryTypes points to: what the build-time tool
/// momenta_compile_types writes (core/lang/compile_types_tool.cc).
std::string CompileLibraryTypes();

}  // namespace momenta
