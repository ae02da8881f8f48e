#pragma once
/// The flat system: every variable, parameter and equation of a model after instantiation and
/// connection, in the user's names, as flattening makes it (core/flatten/flatten.h). The passes
/// work on an EquationSystem made from it (core/passes/equation_system.h), which shares its
/// expression pool and refers to its records.

#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/lang/component_type.h"
#include "core/expr/expr.h"
#include "core/expr/expr_algebra.h"
#include "core/lang/model_spec.h"

namespace momenta {

/// FlatVariable::state_priority of stateSelect never, default, prefer and always (MSL's
/// StateSelect; avoid is -1).
constexpr int kStateNever = -2, kStateDefault = 0, kStatePrefer = 1, kStateAlways = 2;

/// A name, unit, doc or text of the flat system, made when it is needed (a message, `check -v`,
/// an output column) rather than held by each record: a model of 100 000 components would
/// otherwise carry a million strings (docs/ARRAY-BUILD.md). FlatSystem makes the string
/// (VariableName, EquationText, ...).
struct TextRef {
  enum Kind : uint8_t {
    kNone,         ///< ""
    kOwned,        ///< FlatSystem::texts[a]: what no type gives (the model's own names, what passes add)
    kType,         ///< entry b of the names of instance a's type (TypeNames), after the instance's path
    kEqual,        ///< "<variable a> = <variable b> (connection)"
    kUnconnected,  ///< "<variable a> = 0 (unconnected)"
    /// "sum of <flow> over {<connectors>} = 0 (connection)", of the b flow variables from
    /// FlatSystem::connection_vars[a]
    kFlowSum,
  };
  Kind kind = kNone;
  uint32_t a = 0, b = 0;
};

/// The local names of one component type's variables and parameters ("flange_a.s", "mass.m"),
/// their units and docs, and the texts of its equations and when-clauses: held once per type
/// for all its instances.
struct TypeNames {
  std::vector<std::string> vars, var_units;
  std::vector<std::string> params, param_units, param_docs;
  std::vector<std::string> equations;  ///< as written; '\x01' stands for the instance's path and a dot
  std::vector<std::string> whens;      ///< as written
};

// The records below are held per scalar variable, parameter, equation and instance of a model
// (millions in a large one): their fields are ordered by size so that no padding falls between
// them (FlatVariable 88 -> 64 bytes, FlatParameter 104 -> 96, FlatInstance 64 -> 40).

/// 48 bytes: the largest member first, the flags in bits (a flat system holds one per scalar).
struct FlatVariable {
  double nominal = 1.0;
  SourceLoc loc;          ///< where start/fixed were given, else where declared
  /// Full path, e.g. "A.flange_a.s" (FlatSystem::VariableName); its unit is its type's
  /// (FlatSystem::VariableUnit).
  TextRef name;
  ExprId start;      ///< parameter-only start value (invalid: 0)
  InstanceId instance;    ///< owner; invalid for the model's own variables
  /// For a variable that index reduction made for a derivative (a dummy derivative, or a state of
  /// the first-order form of der(der(x))): it stands for der^derivative_order(derivative_of).
  VarId derivative_of;
  uint16_t derivative_order = 0;  ///< at most the parser's depth (256) plus kMaxDifferentiations
  ValueType type = ValueType::kReal;
  int8_t state_priority : 4 = 0;  ///< stateSelect: never -2, avoid -1, default 0, prefer 1, always 2
  bool fixed : 1 = false;
  bool is_flow : 1 = false;
  bool is_input : 1 = false;  ///< an unconnected signal input would be one of these
  /// Constant between events: Boolean and Integer variables, Reals assigned in when-clauses,
  /// impact contact modes.
  bool discrete : 1 = false;
};
static_assert(sizeof(FlatVariable) == 48, "a flat variable is 48 bytes");

struct FlatParameter {
  /// The bounds its value is checked against; infinite where none is declared.
  double min = -std::numeric_limits<double>::infinity(), max = std::numeric_limits<double>::infinity();
  SourceLoc loc;       ///< where its value was set
  TextRef name;      ///< "mA" for a model parameter, "A.m" for a component's (FlatSystem::ParameterName)
  TextRef unit, doc;
  ExprId binding;    ///< an expression of other parameters and constants
  InstanceId instance; ///< invalid for model parameters
  ValueType type = ValueType::kReal;
  bool evaluate = false;  ///< declared `evaluate: true` (FoldStructuralConditions folds it)
};

enum class EquationOrigin : uint8_t { kComponent, kModel, kConnection, kUnconnectedFlow, kFixedStart, kInitial };

struct FlatEquation {
  SourceLoc loc;
  ExprId residual;  ///< lhs - rhs; invalid for an equation the build did not make (DeferredEquations)
  InstanceId instance;  ///< the component whose equation it is (kComponent)
  TextRef text;         ///< the equation as written, or a description (FlatSystem::EquationText)
  /// Index reduction: the flat equation this one is the time derivative of (-1: as written).
  int32_t differentiated_from = -1;
  /// How many times the written equation was differentiated (at most kMaxDifferentiations).
  uint16_t differentiations = 0;
  EquationOrigin origin = EquationOrigin::kComponent;
  /// Of a conditional block (`0 = if guard then lhs - rhs else 0`): dropped when its guard folds
  /// to false (core/passes/structural_conditions.h).
  bool guarded = false;
};
static_assert(sizeof(FlatEquation) == 40, "a flat equation is 40 bytes");

/// Equations that a build does not make as expressions (Flatten's `defer_equations`): those that
/// alias elimination surely removes, x = ±y + c or x = c over two (one) continuous variables with
/// a number c: copies of such component equations (a connector's potential equal to its
/// component's, a flow equal to minus a force) and connection equations between two variables.
/// Alias elimination reads their forms (FlatEquation::residual is invalid until then); it makes one
/// only in case it stays, which such a form never does. Only equations that the passes before it
/// leave alone are deferred: none with an if-expression, none with a table, none naming a
/// variable of a conditional connector.
class DeferredEquations {
 public:
  virtual ~DeferredEquations() = default;
  /// Whether flat equation k is deferred; its terms (variable, coefficient) and its constant offset.
  virtual bool Form(uint32_t k, std::vector<std::pair<VarId, double>>* terms, double* offset) const = 0;
  /// Makes flat equation k's residual: the nodes flattening would have made.
  virtual ExprId Make(uint32_t k) const = 0;
};

/// A component instance. Its path ("A", "R[3]", "R[3].mass") is made on demand
/// (FlatSystem::InstancePath): from its block's name and its index for an element of a `count:`
/// array or a part of one, else held (FlatSystem::texts).
struct FlatInstance {
  const ComponentType* type = nullptr;
  SourceLoc loc;     ///< the component entry in the model file
  /// Its type's names (FlatSystem::type_names), for a component of the model; a composite's
  /// parts are named through the component that holds them (-1).
  int32_t names = -1;
  int32_t block = -1;  ///< its FlatSystem::blocks entry, or -1
  uint32_t path_text = 0;  ///< outside a block: its path, FlatSystem::texts[path_text]
};

/// A `count:` array of components (docs/ARRAY-BUILD.md): `count` elements of one type,
/// made one after the other. Element k (0-based) is the instance first_instance + stride·k (a
/// composite's parts follow it, at the offsets 1 … stride - 1, named part_paths), with the
/// variables first_var + vars_per·k + local, the parameters first_param + params_per·k + local,
/// the equations first_equation + equations_per·k + local and the initial equations
/// first_initial + initials_per·k + local (local: the type's layout, the same for every element).
struct FlatBlock {
  std::string name;  ///< the component entry's name: "R"
  const ComponentType* type = nullptr;
  SourceLoc loc;     ///< the component entry
  InstanceId first_instance;
  VarId first_var;
  ParamId first_param;
  uint32_t first_equation = 0, first_initial = 0;
  uint32_t count = 0;
  uint32_t stride = 1;
  uint32_t vars_per = 0, params_per = 0, equations_per = 0, initials_per = 0;
  std::vector<std::string> part_paths;  ///< a composite's parts, relative: "mass", "arm.joint"
};

/// A when-clause: at the event where `condition` becomes true, `assigns` set discrete variables and
/// `reinits` give states new values (right-hand sides may use pre()).
struct FlatWhen {
  ExprId condition;
  std::vector<std::pair<VarId, ExprId>> assigns, reinits;
  InstanceId instance;
  TextRef text;  ///< FlatSystem::WhenText
  SourceLoc loc;
};

/// An exact impact (see ImpactDecl). `mode_equation` indexes the generated equation
/// `0 = if contact then der(velocity) else force` in FlatSystem::equations.
struct FlatImpact {
  ExprId gap, velocity, restitution, v_small, release;
  VarId force, contact;
  uint32_t mode_equation = 0;
  InstanceId instance;
  SourceLoc loc;
};

/// A table parameter of an instance (docs/FORMAT.md, "Tables"): rows × cols elements, row by
/// row, in the consecutive parameters from `first`, named `name[i,j]` (`name[i]` for a vector).
struct FlatTable {
  std::string name;  ///< "friction.f_pos"
  ParamId first;
  uint32_t rows = 0, cols = 0;
  InstanceId instance;
  SourceLoc loc;  ///< where its value was given
  /// Read by timeTable(): by row r, 1 when t_r = t_{r+1} at the build (a jump), which must stay
  /// so; every other abscissa increases strictly. Empty: all increase strictly.
  std::vector<uint8_t> jumps;
};

/// A connector that exists only when a Boolean parameter of its component is true
/// (ConnectorDecl::condition). Its variables are in the flat system either way; the build
/// decides from the parameter's value whether they are the connector's or absent
/// (core/passes/conditional_connectors.h).
struct FlatConditionalConnector {
  InstanceId instance;
  std::string name;          ///< the connector's name in its type, e.g. "heatPort"
  ParamId condition;         ///< the instance's Boolean parameter, e.g. "damper.useHeatPort"
  VarId first_var;           ///< its potentials, then its flows
  uint32_t num_potentials = 0, num_flows = 0;
  SourceLoc connected_at;    ///< the first connection naming it; unknown when unconnected
  /// Decided when its instance was made (core/flatten/decided_conditions.h): 0 absent (the
  /// instance's equations that hold only with it and its unconnected flows' were not made), 1
  /// present; -1 left to the passes.
  int8_t decided = -1;
};

/// A part of a composite type that exists only when its condition is true (ComponentSpec::condition,
/// Modelica's `Der derv[3] if use_v`). Its variables and equations are in the flat system either
/// way; the build decides from the parameters whether the part is there or absent, with every
/// connection to it (core/passes/conditional_connectors.h).
struct FlatConditionalPart {
  InstanceId instance;        ///< the part; its own parts at every depth follow it
  uint32_t num_instances = 0;  ///< itself and its parts
  InstanceId owner;           ///< the composite instance whose part it is
  ExprId condition;           ///< over parameters
  std::string condition_text;  ///< as written in the composite type, e.g. "use_r and use_v"
  VarId first_var;
  uint32_t num_vars = 0;
  SourceLoc loc;  ///< the condition
};

struct FlatOutput {
  std::string text;
  ExprId expr;
  SourceLoc loc;
  /// Its unit: a variable's or parameter's declared unit, an expression's dimension in the
  /// words of core/lang/units.h ("N.m", "m/s"), or "" when not known.
  std::string unit;
};

/// The parameters that shaped the structure (a count, a connection index, a structural
/// condition, a conditional connector's or part's condition), by id, with the values they shaped
/// it with: a run that gives one another value needs a new build. A value per parameter once one
/// is set (a million conditional connectors' conditions were as many names in a map).
class StructuralParameters {
 public:
  void Set(ParamId p, double value) {
    if (values_.size() <= p.value()) values_.resize(p.value() + 1, kNot);
    values_[p.value()] = value;
  }
  /// The value `p` shaped the structure with; null when it did not.
  const double* Find(ParamId p) const {
    return p.value() < values_.size() && !std::isnan(values_[p.value()]) ? &values_[p.value()] : nullptr;
  }

 private:
  static constexpr double kNot = std::numeric_limits<double>::quiet_NaN();
  std::vector<double> values_;  ///< by parameter; NaN: not structural
};

struct FlatSystem {
  std::shared_ptr<ExprPool> pool;
  std::string model_name, file;
  std::vector<FlatVariable> variables;
  std::vector<FlatParameter> parameters;
  std::vector<ParamId> parameter_order;  ///< every binding's parameters come before it
  std::vector<FlatEquation> equations;
  std::vector<FlatEquation> initial_equations;  ///< from initial_equations: (fixed starts are on the variables)
  std::vector<FlatInstance> instances;
  std::vector<FlatBlock> blocks;  ///< the model's count: arrays, in the order of its components
  std::vector<FlatWhen> whens;
  std::vector<FlatImpact> impacts;
  std::vector<FlatTable> tables;
  std::vector<FlatOutput> outputs;
  /// The model's signal inputs connected to nothing (a component's RealInput left open). A build
  /// refuses them, unless it holds them as inputs (BuildOptions::hold_free_inputs).
  std::vector<VarId> free_inputs;
  std::vector<FlatConditionalConnector> conditional_connectors;
  std::vector<FlatConditionalPart> conditional_parts;
  /// The if-expressions' conditions folded when the instances were made (decided conditional
  /// connectors), counted as FoldStructuralConditions counts those it folds.
  size_t conditions_decided = 0;
  ExperimentSpec experiment;
  std::shared_ptr<const Library> defines;  ///< the model's own types (instances point into them)
  /// The model's own connectors, records and functions laid over the library (null: none), which
  /// the layouts point into.
  std::shared_ptr<const Library> model_library;
  StructuralParameters structural;
  /// The names of each component type instantiated, shared by the copies passes make.
  std::vector<std::shared_ptr<const TypeNames>> type_names;
  std::vector<std::string> texts;          ///< TextRef::kOwned
  /// The units of the model's own variables, which come first (by variable); a component's
  /// variable has its type's unit, one a pass adds none.
  std::vector<TextRef> model_variable_units;
  std::vector<VarId> connection_vars;      ///< TextRef::kFlowSum
  /// The equations still to be made (only from Flatten with `defer_equations`); the build hands
  /// it to the first alias elimination and drops it after.
  std::shared_ptr<const DeferredEquations> deferred;

  /// Holds `text` and returns its reference (an empty text needs none).
  TextRef Own(std::string text);
  /// "A", "R[3]", "R[3].mass": made from the instance's block, or the held path.
  std::string InstancePath(InstanceId i) const;
  /// Whether `text` starts with instance i's path (compared in place); sets `*length` to the
  /// path's length when it does.
  bool StartsWithPath(InstanceId i, std::string_view text, size_t* length) const;
  std::string VariableName(VarId v) const;
  const std::string& VariableUnit(VarId v) const;
  std::string ParameterName(ParamId p) const;
  const std::string& ParameterUnit(ParamId p) const;
  const std::string& ParameterDoc(ParamId p) const;
  std::string EquationText(const FlatEquation& eq) const;
  std::string WhenText(const FlatWhen& w) const;
  /// The parameter of that full name, compared in place with every parameter's (no map of every
  /// name is held); nullopt when there is none.
  std::optional<ParamId> FindParameter(const std::string& name) const;
  /// The value the parameter called `name` shaped the structure with; null when it did not (or
  /// there is none of that name).
  const double* StructuralValue(const std::string& name) const {
    const std::optional<ParamId> p = FindParameter(name);
    return p ? structural.Find(*p) : nullptr;
  }

  ExprNamer Namer() const;
  /// "component A (Mass) at model.yaml:12:3, equation 'm*a = flange_a.f + flange_b.f'".
  std::string DescribeEquation(const FlatEquation& eq) const;
  /// "A.s (Mass at model.yaml:12:3)".
  std::string DescribeVariable(VarId v) const;
};

/// Parameter overrides from the command line: name -> value.
using ParameterOverrides = std::map<std::string, double>;

/// The unit of each column `output_names` names (an output's text or a variable's name, as a
/// compiled model's output_names), "" where not known; `time` is not among them.
std::vector<std::string> OutputUnits(const FlatSystem& flat,
                                     const std::vector<std::string>& output_names);

}  // namespace momenta
