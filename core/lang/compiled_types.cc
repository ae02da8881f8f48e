// The tables momenta_compile_types wrote when the binary was built (compiled_library_types.inc).

#include "core/lang/compiled_types.h"

#include <cstdint>
#include <iterator>

namespace momenta {

namespace {
#include "compiled_library_types.inc"
}  // namespace

CompiledLibraryTypes CompiledBuiltinTypes() {
  CompiledLibraryTypes types;
  types.library_hash = kCompiledLibraryHash;
  types.bytes = kCompiledLibraryBytes;
  types.offsets = kCompiledLibraryOffsets;
  types.entries = std::size(kCompiledLibraryOffsets) - 1;  // the entries' ranges and the start's
  return types;
}

}  // namespace momenta
