#pragma once
/// The component library compiled into the binary (components/*.yaml, embedded at build time).

#include "core/lang/component_type.h"

namespace momenta {

/// The library compiled into the binary (components/*.yaml).
const Library& BuiltinLibrary();

}  // namespace momenta
