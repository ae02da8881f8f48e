#pragma once
/// A component type prepared for instantiation: its local names (a composite's include every
/// part's, under their relative paths) and templates of every equation, start value and parameter
/// binding over local indices. TypeLayoutBuilder prepares each type once, however many instances
/// it has; each instance then only copies the templates with its own offsets (instances.h), so
/// flattening stays linear in the number of components.

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "core/flatten/equation_template.h"
#include "core/flatten/flat_system.h"
#include "core/flatten/flatten_context.h"
#include "core/lang/component_type.h"

namespace momenta::flatten_internal {

struct LocalVar {
  std::string name;                    ///< "s", "flange_a.f", or in a composite "mass.s"
  const VariableDecl* decl = nullptr;  ///< declaration (for signal connectors: optional)
  bool is_flow = false;
  bool is_input = false;
  ValueType type = ValueType::kReal;
  std::string unit;
  int32_t sub = -1;            ///< the part of a composite it belongs to (-1: the type itself)
  std::optional<bool> fixed;   ///< set by a composite's modifier
  std::optional<int> state_priority;  ///< stateSelect, set by a composite's modifier
  std::optional<double> nominal;      ///< set by a composite's modifier
  SourceLoc loc;               ///< a composite's modifier, if one sets it
  bool counted = true;         ///< by the local balance (an overdetermined record's residues only)
};

struct LocalParam {
  std::string name;
  const ParameterDecl* decl = nullptr;
  int32_t sub = -1;
  SourceLoc loc;  ///< a composite's modifier, if one sets it
};

struct ConnectorSlot {
  const ConnectorDecl* decl;
  const ConnectorType* type;
  uint32_t first_local_var;  ///< potentials then flows, or the one signal variable
};

/// A part of a composite type, at any depth: "mass", "arm.joint", "links[2]".
struct SubInstance {
  std::string path;
  const TypeLayout* layout;
  SourceLoc loc;  ///< its component entry
  uint32_t first_var, first_param;
  /// A conditional part's condition over the composite's local parameters (root -1: the part
  /// always exists), as written, and where.
  Template condition;
  std::string condition_text;
  SourceLoc condition_loc;
};

/// Where an equation or a when-clause of a layout comes from, for messages and instance records.
struct PartInfo {
  std::string text;  ///< as written; '\x01' stands for the instance's path and a dot
  SourceLoc loc;
  int32_t sub = -1;
  EquationOrigin origin = EquationOrigin::kComponent;
  bool guarded = false;  ///< of a conditional block (FlatEquation::guarded)
};

struct TypeLayout {
  const ComponentType* type = nullptr;
  std::vector<LocalVar> vars;
  std::vector<LocalParam> params;
  std::unordered_map<std::string, uint32_t> var_index;
  std::unordered_map<std::string, uint32_t> param_index;
  /// A table parameter (shape: [":", 2]): each instance sizes it from its value.
  struct TableSlot {
    const ParameterDecl* decl = nullptr;
    uint32_t rows = 0, cols = 0;     ///< of the default value
    std::vector<Template> defaults;  ///< the default value's elements, row by row
  };
  std::vector<TableSlot> tables;
  std::unordered_map<std::string, uint32_t> table_index;
  std::vector<ConnectorSlot> connectors;  ///< the type's own connectors
  std::unordered_map<std::string, uint32_t> connector_index;
  std::vector<Template> equations, initial_equations, param_defaults, starts;
  std::vector<PartInfo> equation_info, initial_info, when_info;
  struct WhenTemplate {
    Template condition;
    std::vector<std::pair<uint32_t, Template>> assigns, reinits;  ///< local variable, value
  };
  std::vector<WhenTemplate> whens;
  struct ImpactTemplate {
    Template gap, velocity, restitution, v_small, release;
    uint32_t force = 0, contact = 0;
    const ImpactDecl* decl = nullptr;
    int32_t sub = -1;
  };
  std::vector<ImpactTemplate> impacts;
  std::vector<bool> discrete;  ///< by local variable
  std::vector<SubInstance> subs;
  /// Equations the local balance does not count (ComponentType::uncounted_equations, its parts'
  /// and the connections' equalities of uncounted record elements).
  size_t uncounted_equations = 0;
  /// The parts' connectors that a connection inside the type names, by the local index of the
  /// connector's first variable (at any depth): where the first such connection is written.
  std::unordered_map<uint32_t, SourceLoc> connected;
  std::vector<std::string> LocalNames() const {
    std::vector<std::string> names;
    for (const auto& v : vars) names.push_back(v.name);
    for (const auto& p : params) names.push_back(p.name);
    return names;
  }
};

/// Every type's layout, by type: they outlive flattening when deferred equations read their
/// templates (DeferredAliases::Keep).
using TypeLayouts = std::unordered_map<const ComponentType*, std::unique_ptr<TypeLayout>>;

/// Lays out each component type once, on first use, with its parts before it.
class TypeLayoutBuilder {
 public:
  explicit TypeLayoutBuilder(FlattenContext* context) : context_(*context) {}

  /// The layout of `type`. `user` is the component entry (of the model, or of the composite that
  /// holds it) whose type it is, which the messages about the type name; null for none.
  const TypeLayout& Layout(const ComponentType* type, const ComponentSpec* user);
  /// Hands over every layout made (the flat system's deferred equations read their templates).
  TypeLayouts TakeLayouts() { return std::move(layouts_); }

 private:
  /// Refuses a type that holds itself, or nests deeper than kMaxTypeDepth.
  void CheckNesting(const ComponentType* type, const ComponentSpec* user) const;

  FlattenContext& context_;
  TypeLayouts layouts_;
  std::vector<const ComponentType*> laying_out_;  ///< types being laid out (cycle detection)
};

/// Estimated bytes of one instance of a type through the build (core/base/memory_budget.h).
double EstimatedBytes(const TypeLayout& layout);

/// `n` instances of `layout` for component entry `c` (`what`: "count of R", `text`: as written),
/// checked: a whole number of at least 1 whose components fit, with the rest of the model, in
/// the memory budget and in momenta's 32-bit indices. Tells the build's watch how large the build
/// is planned to be (NotePlannedBuild).
uint32_t CheckedCount(FlattenContext* context, const ComponentSpec& c, const TypeLayout& layout, double n,
                      std::string what, const std::string& text);

/// The elements of a table's value row by row, with its rows and columns: a list of rows of one
/// length (`[[0, 1], [1, 2]]`) for a matrix table, a list of numbers for a vector (one column).
/// The declared fixed sizes must match. `who` names the table in messages.
std::vector<AstPtr> TableElements(const AstPtr& value, const ParameterDecl& decl, const SourceLoc& loc,
                                  const std::string& who, uint32_t* rows, uint32_t* cols);

/// Whether a modifier leaves a parameter free: `{fixed: false}` without a value (free_parameters.h).
bool IsFreeParameter(const Modifier& m);
/// Which parameter (first = true) or variable of `layout` a modifier of component `c` sets.
std::pair<bool, uint32_t> ModifierTarget(const ComponentSpec& c, const TypeLayout& layout, const Modifier& m);

/// A parameter modifier's value; one written with a unit (`m: 40 kg`) converted to the
/// parameter's declared unit.
AstPtr ModifierValue(const Modifier& m, const ParameterDecl& target, const std::string& component);

}  // namespace momenta::flatten_internal
