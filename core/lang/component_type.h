#pragma once
/// Component and connector types as declared in a library file or a model's `define:` section
/// (docs/FORMAT.md). Declarations only: names are resolved when a type is first instantiated.

#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/lang/ast.h"
#include "core/lang/short_names.h"
#include "core/base/error.h"
#include "core/base/messages.h"

namespace momenta {

enum class ValueType : uint8_t { kReal, kInteger, kBoolean };

/// The fixed shape of an array declaration (docs/FORMAT.md, "Vectors and matrices"): empty for a
/// scalar, {n} for a vector, {n, m} for a matrix.
using Shape = std::vector<int>;
/// A size given by the value (`shape: [":", 2]`): only in the shape of a table parameter.
constexpr int kOpenSize = -1;
inline bool IsOpen(const Shape& shape) {
  for (int n : shape) {
    if (n == kOpenSize) return true;
  }
  return false;
}
/// Local name → shape of the arrays a type was declared with (its scalar form names the elements
/// `r[1]`, `R[1,2]`; core/lang/arrays.h).
using ArrayShapes = std::map<std::string, Shape>;
const char* ValueTypeName(ValueType t);

struct ParameterDecl {
  std::string name;
  AstPtr value;  ///< default binding: a number or an expression of the type's other parameters
  std::string value_text;
  std::string unit, doc;
  std::optional<double> min, max;
  ValueType type = ValueType::kReal;
  Shape shape;  ///< declared `shape:`; empty for a scalar
  bool evaluate = false;  ///< `evaluate: true`: its value is fixed when the model is built
  SourceLoc loc;
};

struct VariableDecl {
  std::string name;
  std::string unit, doc;
  AstPtr start;  ///< null: 0 (or false)
  bool fixed = false;
  double nominal = 1.0;
  std::optional<double> min, max;
  /// `stateSelect:` never -2, avoid -1, default 0, prefer 1, always 2 (MSL's StateSelect).
  int state_priority = 0;
  ValueType type = ValueType::kReal;
  Shape shape;  ///< declared `shape:`; empty for a scalar
  /// `type:` a record (docs/FORMAT.md, "Records"): the declaration stands for its fields, which
  /// the record expansion (core/lang/records.h) declares as `name.field`; empty otherwise.
  std::string record;
  /// Whether the local balance counts it: an overdetermined record's elements beyond its
  /// residues do not (Modelica counts an orientation as 3, not 12).
  bool counted = true;
  SourceLoc loc;
};

/// A branch of a conditional equation block (`- if: … then: … else: …`): block `block` of the
/// type (ComponentType::blocks), branch `branch` (0 then, 1 else).
struct BlockBranch {
  uint32_t block = 0, branch = 0;
};

struct EquationDecl {
  std::string text;
  AstEquation ast;
  SourceLoc loc;
  /// The structural condition under which it holds (the conjunction of its blocks' conditions,
  /// core/lang/records.h), or null for an equation that always holds.
  AstPtr guard;
  /// Its blocks, outermost first; empty outside any block.
  std::vector<BlockBranch> blocks;
  bool counted = true;  ///< as VariableDecl::counted, for the elements of a record equation
};

/// One statement of a when-clause: `reinit(x, expr)` or the discrete assignment `x = expr`.
struct StatementDecl {
  bool is_reinit = false;
  std::string target;  ///< the variable assigned or re-initialised
  AstPtr value;
  std::string text;
  SourceLoc loc;
};

/// `when: cond` with its statements: executed at the event where cond becomes true.
struct WhenDecl {
  std::string text;
  AstPtr condition;
  std::vector<StatementDecl> statements;
  SourceLoc loc;
};

/// An exact impact (docs/FORMAT.md, "Impacts"): when `gap` reaches zero while `velocity` < 0,
/// velocities jump so that the model's integrated equations hold and velocity reverses by
/// `restitution`; below `v_small` the contact closes and rests until `release` holds. The
/// machinery adds the equation `0 = if contact then der(velocity) else force`.
struct ImpactDecl {
  AstPtr gap, velocity, restitution, v_small, release;
  std::string gap_text, velocity_text, restitution_text, v_small_text, release_text;
  std::string force, contact;  ///< variable names
  SourceLoc loc;
};

/// One value of a drawn shape: an expression in the component's scope of the shape the kind
/// gives the field (`shape`: empty for a scalar, [2] a planar point or direction, [3] a 3-vector,
/// [3, 3] a transformation matrix).
struct ShapeField {
  std::string key, text;
  AstPtr expr;
  Shape shape;
  SourceLoc loc;
};

/// `animation:` of a component type (docs/FORMAT.md, "Animation"): one shape drawn in the
/// report's scene from quantities recorded during the run. Planar kinds and their fields: circle
/// (at, radius, angle), line and spring (from, to), pin and ground (at), wall (at, normal, start,
/// end). 3-D kinds (`space`), as the MSL's Visualizers.Advanced.Shape places them: sphere, box,
/// cylinder, cone, pipe, beam, gearwheel and spring (r, T, r_shape, length_direction,
/// width_direction, length, width, height, color, extra), frame (r, T, length, color) and line3d
/// (from, to, color).
struct ShapeDecl {
  std::string kind;
  bool space = false;  ///< a 3-D shape (a spring with `r` is one)
  std::vector<ShapeField> fields;
  SourceLoc loc;
};

struct ConnectorVariable {
  std::string name, unit, doc;
  Shape shape;  ///< declared `shape:`; empty for a scalar
  std::string record;   ///< `type:` a record (a potential only); empty otherwise
  bool counted = true;  ///< as VariableDecl::counted
};

/// `kind: record` (docs/FORMAT.md, "Records"): named fields, each a scalar or an array. An
/// overdetermined record (Modelica's orientation object) counts as its `residues` in a type's
/// balance, as an unknown and as an equation, and its connections form the connection graph
/// (core/flatten/connection_graph.h).
struct RecordType {
  std::string name, doc;
  std::vector<ConnectorVariable> fields;
  int residues = 0;  ///< 0: not overdetermined
  SourceLoc loc;
};

/// `kind: function`: a function whose body is one expression (or, returning a record, one per
/// field), inlined where it is called (core/lang/array_expression.h).
struct FunctionDecl {
  struct Input {
    std::string name;
    Shape shape;         ///< empty: a scalar (or a record)
    std::string record;  ///< a record input's type
  };
  std::string name, doc;
  std::vector<Input> inputs;
  AstPtr value;                               ///< the body, or null for a record value
  std::string value_text;
  std::string record;                         ///< the record type it returns, if any
  std::vector<std::pair<std::string, AstPtr>> fields;  ///< a record value: field → expression
  std::vector<std::string> field_texts;
  SourceLoc loc;
};

/// `roots:`, `potential_roots:` or `branches:` of a type (Modelica's Connections.root,
/// potentialRoot and branch): record potentials of its connectors, `b` for a branch's other end.
struct GraphDecl {
  std::string a, b;
  int priority = 0;          ///< a potential root's
  std::string condition;     ///< a Boolean parameter (`not p` negates), or empty: always
  SourceLoc loc;
};

struct ConnectorType {
  std::string name, doc;
  bool is_signal = false;
  bool is_input = false;  ///< signals: input (true) or output (false)
  ValueType signal_type = ValueType::kReal;
  std::vector<ConnectorVariable> potentials, flows;
  ArrayShapes arrays;  ///< the shaped variables its scalar form came from
  /// Its record potentials (`R` → `Orientation`), whose fields' elements are potentials
  /// `R.T[1,1]` … (core/lang/records.h).
  std::map<std::string, std::string> records;
  SourceLoc loc;
};

struct ConnectorDecl {
  std::string name, type, doc;
  Shape shape;  ///< a signal connector carrying a vector or matrix; empty for a scalar
  /// A Boolean parameter of the type: the connector exists only when it is true (MSL's
  /// `HeatPort heatPort if useHeatPort`); empty for a connector that always exists.
  std::string condition;
  SourceLoc loc;
};

/// `key: value` in a component entry: a parameter value, or start/fixed/nominal/min/max/stateSelect
/// of a variable.
struct Modifier {
  std::string key;
  AstPtr value;      ///< parameter value; null for a variable modifier
  std::string value_text;
  /// The unit a value was written with (`m: 40 kg`): `value` is the number, converted to the
  /// parameter's declared unit when the type is known. Empty for a plain value.
  std::string value_unit;
  AstPtr start;      ///< variable modifier: start value (may be null)
  std::optional<bool> fixed;
  std::optional<int> state_priority;  ///< stateSelect, as VariableDecl::state_priority
  std::optional<double> nominal;      ///< > 0: scales the variable's absolute tolerance
  std::optional<double> min, max;     ///< the variable's range, as VariableDecl::min and max
  SourceLoc loc;      ///< the value
  SourceLoc key_loc;  ///< the key
};

struct ComponentSpec {
  std::string name, type, doc;
  AstPtr count;  ///< null for a single component
  /// A part of a composite type that exists only when this expression of the type's parameters
  /// is true (Modelica's `Der derv[3] if use_v`); null for a part that always exists.
  AstPtr condition;
  std::string condition_text;
  SourceLoc condition_loc;
  std::vector<Modifier> modifiers;
  SourceLoc loc, type_loc;
};

struct ConnectionSpec {
  /// The ends' trees, or null for an end that is a plain dotted name (`sd1.flange_b`,
  /// IsPlainName): its text gives it (EndA, EndB). A written-out model has 200 000 such ends,
  /// 270 bytes each as trees, held from reading to flattening.
  AstPtr a, b;
  std::string a_text, b_text;
  std::string loop_var;  ///< empty unless `for:`
  AstPtr loop_from, loop_to;
  std::string loop_text;  ///< the `for:` text, e.g. "i in 1:n-1"
  SourceLoc loop_loc;     ///< where the `for:` text starts
  SourceLoc loc, a_loc, b_loc;

  /// The tree of end a or b: the one held, or the plain name parsed from its text.
  AstPtr EndA() const;
  AstPtr EndB() const;
};

struct ComponentType {
  std::string name, doc;
  std::vector<ParameterDecl> parameters;
  /// Parameters whose size their value gives (`shape: [":", 2]`, docs/FORMAT.md "Tables"): each
  /// instance has its own number of rows; equations read them through interpolate().
  std::vector<ParameterDecl> tables;
  std::vector<ConnectorDecl> connectors;
  std::vector<VariableDecl> variables;
  std::vector<EquationDecl> equations;
  std::vector<EquationDecl> initial_equations;
  std::vector<WhenDecl> whens;
  std::vector<ImpactDecl> impacts;
  std::vector<ShapeDecl> animation;  ///< what the report's scene draws for an instance
  /// A composite type's parts: components of other types and the connections between them and
  /// to the type's own connectors (an own connector is named alone: [flange_a, mass.flange_a]).
  std::vector<ComponentSpec> components;
  std::vector<ConnectionSpec> connections;
  ArrayShapes arrays;  ///< in its scalar form: the arrays it was declared with (core/lang/arrays.h)
  /// `outer: {world: World}`: the names under `world.` are the parameters of the model's
  /// component `world` (Modelica's inner/outer; core/lang/records.h declares them).
  std::map<std::string, std::string> outers;
  /// The connection graph's declarations (core/flatten/connection_graph.h).
  std::vector<GraphDecl> roots, potential_roots, branches;
  /// Conditional equation blocks: where each is written (EquationDecl::blocks indexes it).
  std::vector<SourceLoc> blocks;
  /// Local record names (`R_rel`, `frame_a.R`) → their record type, after the record expansion.
  std::map<std::string, std::string> records;
  /// Equations of its scalar form that the local balance does not count: the elements of
  /// record equations beyond the residues, and all branches of a block but one.
  size_t uncounted_equations = 0;
  bool scalar_form = false;  ///< made by ScalarForm (core/lang/arrays.h), which runs once
  SourceLoc loc;
  bool user_defined = false;  ///< from a model's define: section, a uses: file or a model file
};

/// The types a model can use: the built-in library plus the model's own definitions.
/// Domain libraries name their types with a package prefix (`Rotational.Fixed`,
/// `Planar.Body`); a type is found by its full name, or by its last part alone (`Body`) when no
/// unqualified type has that name and no other package uses it.
class Library;

/// Component types a library reads on first use (the built-in library: reading all of its text
/// at every start would cost more than most runs' integration, core/lang/builtin_library.cc).
class LazyTypes {
 public:
  virtual ~LazyTypes() = default;
  /// Reads into `library` the component type that `name` names (by its full name, or by its last
  /// part as Library finds it), when there is one not read yet.
  virtual void Read(const std::string& name, Library* library) const = 0;
  /// Reads every type not read yet.
  virtual void ReadAll(Library* library) const = 0;
  /// Reads every function not read yet (a source that reads them at once has nothing to do).
  virtual void ReadFunctions(Library*) const {}
};

class Library {
 public:
  Library() = default;
  /// A copy holds every type of `other`: types `other` reads on first use are read now, and the
  /// copy has no source of its own (a source shared by two libraries would read a type into only
  /// one of them, and the other would never ask again).
  Library(const Library& other);
  Library& operator=(const Library& other);
  Library(Library&&) noexcept = default;
  Library& operator=(Library&&) noexcept = default;
  ~Library() = default;

  /// From now on, a component type not found is asked of `lazy` first. The library's contents do
  /// not change (a type read on first use was always in it), so lookups stay const; they are not
  /// safe from several threads at once while types are still being read.
  void SetLazyTypes(std::shared_ptr<const LazyTypes> lazy) { lazy_ = std::move(lazy); }
  /// From now on, what is not found here is looked up in `base` (a model's own connectors,
  /// records and functions over the library it is built with); `base` must outlive every lookup.
  void SetBase(const Library* base) { base_ = base; }
  /// Whether it holds no connector, component, record or function of its own.
  bool empty() const {
    return connectors_.empty() && components_.empty() && records_.empty() && functions_.empty();
  }
  void AddConnector(ConnectorType c);
  void AddComponent(ComponentType c);
  void AddRecord(RecordType r);
  void AddFunction(FunctionDecl f);
  const ConnectorType* FindConnector(const std::string& name) const;
  const RecordType* FindRecord(const std::string& name) const;
  /// By its full name (`Frames.resolve2`) or its last part when one function alone has it.
  const FunctionDecl* FindFunction(const std::string& name) const;
  bool HasRecordsOrFunctions() const { return !records_.empty() || !functions_.empty(); }
  /// Copies the records and functions of `other` (a library read in pieces needs them all).
  void AddRecordsAndFunctions(const Library& other);
  /// Copies the connectors, records and functions of `other` (not its component types).
  void AddOwnEntries(const Library& other);
  const ComponentType* FindComponent(const std::string& name) const;
  bool Has(const std::string& name) const;
  /// A component type of exactly this name (no short-name lookup).
  bool HasComponent(const std::string& name) const;
  std::vector<std::string> ComponentNames() const;
  std::vector<std::string> ConnectorNames() const;
  /// The records' names, this library's own and its base's.
  std::vector<std::string> RecordNames() const;

 private:
  std::map<std::string, std::shared_ptr<ConnectorType>> connectors_;
  std::map<std::string, std::shared_ptr<ComponentType>> components_;
  std::map<std::string, std::shared_ptr<RecordType>> records_;
  std::map<std::string, std::shared_ptr<FunctionDecl>> functions_;
  std::map<std::string, std::string> short_functions_;
  /// Last part of a qualified name -> the full name ("" when two packages share it).
  std::map<std::string, std::string> short_connectors_, short_components_;
  std::shared_ptr<const LazyTypes> lazy_;
  const Library* base_ = nullptr;
  /// Reads `name` through lazy_, if set (a type read now was always in the library).
  void ReadLazily(const std::string& name) const;
};

}  // namespace momenta
