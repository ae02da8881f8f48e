#pragma once
/// A model file as the user wrote it (docs/FORMAT.md), after reading and before flattening.

#include <string>
#include <vector>

#include "core/component_type.h"

namespace momenta {

/// `key: value` in a component entry: a parameter value, or start/fixed of a variable.
struct Modifier {
  std::string key;
  AstPtr value;      ///< parameter value; null for a variable modifier
  std::string value_text;
  AstPtr start;      ///< variable modifier: start value (may be null)
  std::optional<bool> fixed;
  SourceLoc loc;      ///< the value
  SourceLoc key_loc;  ///< the key
};

struct ComponentSpec {
  std::string name, type, doc;
  AstPtr count;  ///< null for a single component
  std::vector<Modifier> modifiers;
  SourceLoc loc, type_loc;
};

struct ConnectionSpec {
  AstPtr a, b;
  std::string a_text, b_text;
  std::string loop_var;  ///< empty unless `for:`
  AstPtr loop_from, loop_to;
  std::string loop_text;  ///< the `for:` text, e.g. "i in 1:n-1"
  SourceLoc loop_loc;     ///< where the `for:` text starts
  SourceLoc loc, a_loc, b_loc;
};

struct OutputSpec {
  std::string text;
  AstPtr expr;
  SourceLoc loc;
};

struct ExperimentSpec {
  double start = 0, stop = 1, tolerance = 1e-6;
  double interval = 0;  ///< 0: (stop - start)/500
  std::string linear_solver = "auto";
  SourceLoc loc;
};

struct ModelSpec {
  std::string name, doc, file;
  std::vector<ParameterDecl> parameters;
  std::vector<ComponentType> defines;
  std::vector<ComponentSpec> components;
  std::vector<ConnectionSpec> connections;
  std::vector<VariableDecl> variables;
  std::vector<EquationDecl> equations, initial_equations;
  std::vector<WhenDecl> whens;
  ExperimentSpec experiment;
  std::vector<OutputSpec> outputs;
  SourceLoc loc;
};

/// Reads a model file. Throws ModelError with file:line:col for anything wrong in it.
ModelSpec LoadModelFile(const std::string& path);
/// Reads a model from text; `file_name` is used in messages.
ModelSpec LoadModelString(const std::string& yaml, const std::string& file_name);
/// Reads a library file's text into `library`.
void LoadLibraryString(const std::string& yaml, const std::string& file_name, Library* library);

}  // namespace momenta
