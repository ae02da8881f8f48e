#pragma once
/// A model file's root as the loader reads it (docs/FORMAT.md): the model's name, its `uses:`
/// files and `define:` types, its own declarations and parts, its `experiment:` section (checked
/// against the limits of core/lang/experiment.h) and its `outputs:`.

#include "core/lang/model_spec.h"
#include "core/lang/yaml_loader_values.h"

namespace momenta {

/// The model of the document whose root is `root`, as written: the files of `uses:` are named,
/// not read (LoadModelString reads them), and arrays are not yet scalar.
ModelSpec ReadModel(const ValueReader& reader, const YamlNode& root);

}  // namespace momenta
