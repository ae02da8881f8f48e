#pragma once
/// An expression written in a component type, read as the model reads it in one instance of that
/// type: what the report's scene needs to add its animation's quantities as model outputs.

#include <string>

#include "core/base/error.h"
#include "core/lang/ast.h"

namespace momenta {

/// A copy of `expr` with every name read in the scope of the instance at `instance_path`
/// (`r` in instance `A` is `A.r`, `R[3].body` prefixes `R[3].body.`); `time` and `pi` stay the
/// model's. Throws ModelError at `loc` when the path is not a name.
AstPtr InInstanceScope(const AstPtr& expr, const std::string& instance_path, const SourceLoc& loc);

}  // namespace momenta
