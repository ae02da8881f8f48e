#pragma once
/// A model file as the user wrote it (docs/FORMAT.md), after reading and before flattening.

#include <memory>
#include <string>
#include <vector>

#include "core/lang/component_type.h"
#include "core/lang/experiment.h"

namespace momenta {

struct OutputSpec {
  std::string text;
  AstPtr expr;
  SourceLoc loc;
};

/// A file named in `uses:`, as written (relative to the model's own file).
struct UsesSpec {
  std::string path;
  SourceLoc loc;
};

struct ModelSpec {
  std::string name, doc, file;
  std::vector<UsesSpec> uses;  ///< read by LoadModelFile: their types are in `defines`
  std::vector<ParameterDecl> parameters;
  std::vector<ComponentType> defines;
  /// The connector types (as written: their records not yet expanded), records and functions of
  /// its `define:` section and of its `uses:` files; Flatten lays them over the library.
  std::shared_ptr<Library> own = std::make_shared<Library>();
  std::vector<ComponentSpec> components;
  std::vector<ConnectionSpec> connections;
  std::vector<VariableDecl> variables;
  std::vector<EquationDecl> equations, initial_equations;
  std::vector<WhenDecl> whens;
  ExperimentSpec experiment;
  std::vector<OutputSpec> outputs;
  SourceLoc loc;
};

}  // namespace momenta
