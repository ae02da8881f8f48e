#pragma once
/// The model and library loader: YAML text or a file in, a ModelSpec or library types out, with
/// file:line:col errors naming the user's component for anything wrong in it (docs/FORMAT.md).

#include <string>

#include "core/lang/component_type.h"
#include "core/lang/model_spec.h"

namespace momenta {

/// A model as a component type (its parameters, variables, equations, components and
/// connections; not its experiment or outputs), so that one model can be a part of another.
ComponentType ModelAsType(const ModelSpec& m);

/// Reads a model file. Throws ModelError with file:line:col for anything wrong in it.
ModelSpec LoadModelFile(const std::string& path);
/// Reads a model from text; `file_name` is used in messages.
ModelSpec LoadModelString(const std::string& yaml, const std::string& file_name);
/// Reads a library file's text into `library`.
void LoadLibraryString(const std::string& yaml, const std::string& file_name, Library* library);

}  // namespace momenta
