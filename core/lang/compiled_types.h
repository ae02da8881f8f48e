#pragma once
/// The library's component types as the build parsed them (momenta_compile_types), in the
/// library momenta_compiled_types: a program that links it hands them to BuiltinLibrary with
/// UseCompiledLibraryTypes(CompiledBuiltinTypes()) and reads no type's text at run time.

#include "core/lang/builtin_library.h"

namespace momenta {

/// The compiled types of this build's library.
CompiledLibraryTypes CompiledBuiltinTypes();

}  // namespace momenta
