#pragma once
/// Vectors and matrices (docs/FORMAT.md, "Vectors and matrices"): the scalar form of a type's or
/// a model's declarations, made before the flattener builds templates, so that the flattener and
/// every later pass see scalar names only.
///
/// A declaration with `shape: [2]` becomes the scalar declarations `r[1]`, `r[2]`; one with
/// `shape: [2, 2]` becomes `R[1,1]`, `R[1,2]`, `R[2,1]`, `R[2,2]` (row by row, Modelica's
/// spelling). Every expression is evaluated on the syntax tree into the scalar trees of its
/// elements — array literals, elementwise `+ -`, scalar `* /`, matrix-matrix and matrix-vector
/// products, the scalar product of two vectors, transpose, cross, norm, identity, zeros, sum,
/// element access with constant subscripts, and elementwise functions (der, sin, …) and
/// if-expressions — and an equation between arrays becomes one scalar equation per element. The
/// work is linear in the size of the declarations and their elements; a type or model without
/// arrays is left as it is.

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "core/lang/component_type.h"
#include "core/lang/model_spec.h"

namespace momenta {

/// The most elements one array may have.
constexpr size_t kMaxArrayElements = 100000;

/// "[2]", "[3, 3]", or "scalar" for the empty shape.
std::string ShapeText(const Shape& shape);

/// The number of elements of an array of `shape` (1 for a scalar).
size_t ElementCount(const Shape& shape);

/// The name of element `flat` (0-based, row-major) of the array `name`: "r[1]", "R[1,2]".
std::string ElementName(const std::string& name, const Shape& shape, size_t flat);

/// The names an expression can see, as far as arrays are concerned.
struct ArrayScope {
  /// The shape of the array a name refers to (its segments' names joined by '.', the subscripts
  /// of the last left out), or null for a scalar or an unknown name (the flattener reports those).
  std::function<const Shape*(const Ast& name)> shape_of;
  /// In the model scope a subscript on a one-segment name may pick an element of a component
  /// array (`R[3]`); everywhere else a subscript on a name that is no array is an error.
  bool component_arrays = false;
  std::string owner;  ///< "Body", for messages; empty in the model scope
  /// The library's records and functions (calls are inlined), or null.
  const Library* library = nullptr;
  /// Local record names → record types (ComponentType::records), or null.
  const std::map<std::string, std::string>* records = nullptr;
};

/// The scope of a type's own names (its scalar form's `arrays`), e.g. for the modifiers of the
/// components it contains. The scope refers to `type`, which must outlive it.
ArrayScope ScopeOf(const ComponentType& type);

/// Whether a type declares arrays or uses array syntax (shape:, `[a, b]`, `r[1]`, array
/// functions, connectors whose type has arrays).
bool NeedsScalarForm(const ComponentType& type, const Library& library);

/// The scalar form of a component type; its `arrays` records the shapes it was declared with.
/// Throws ModelError (file:line:col, the type and both shapes) for a shape mismatch, a subscript
/// out of range or not constant, a start or value of the wrong shape, or a function applied to
/// the wrong shape.
ComponentType ScalarForm(const ComponentType& type, const Library& library);

/// A connector type with its shaped potentials and flows expanded to elements.
ConnectorType ScalarForm(ConnectorType connector);

/// Replaces every component type of `library` that needs it by its scalar form.
void ScalariseLibrary(Library* library);

/// A component's modifiers for its type's scalar form: a whole-array value or start
/// (`r0: [0.5, 4]`, `r: {start: [0, 1], fixed: true}`) becomes one modifier per element (`r0[1]`,
/// `r0[2]`); a scalar applies to every element; `fixed` to all of them. `scope` resolves the names
/// in the values (the enclosing model or type). A value of the wrong shape is a ModelError.
std::vector<Modifier> ScalarModifiers(const ComponentSpec& component, const ComponentType& type,
                                      const ArrayScope& scope);

/// The scalar form of a model: its defines, parameters, variables, equations, when-clauses, its
/// components' modifiers, connections between shaped signal connectors (element by element) and
/// outputs (a whole array: one output per element). Nothing when the model and the types it uses
/// have no arrays.
std::optional<ModelSpec> ScalarModel(const ModelSpec& spec, const Library& library);

}  // namespace momenta
