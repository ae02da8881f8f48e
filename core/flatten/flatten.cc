// Flattening: component instances -> variables, parameters and equations; connections -> the
// equations of each connection set (potentials equal, flows sum to zero, an unconnected flow is
// zero, a signal input equals its one output).
//
// Each component type is prepared once (its local names laid out and its equations resolved into
// templates of local indices); each instance then only copies templates into the expression pool
// with its own offsets, so flattening stays linear in the number of components.

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <optional>
#include <sstream>
#include <unordered_map>
#include <unordered_set>

#include "core/lang/arrays.h"
#include "core/expr/expr_chain.h"
#include "core/flatten/equation_template.h"
#include "core/expr/expr_eval.h"
#include "core/flatten/flat_system.h"
#include "core/base/memory_budget.h"
#include "core/base/messages.h"
#include "core/lang/parser.h"
#include "core/flatten/time_table.h"
#include "core/lang/unit_check.h"
#include "core/flatten/flatten.h"

namespace momenta {

namespace {

// ---------------------------------------------------------------------------------------------
// Type layouts and equation templates

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
  SourceLoc loc;               ///< a composite's modifier, if one sets it
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

struct TypeLayout;

/// A part of a composite type, at any depth: "mass", "arm.joint", "links[2]".
struct SubInstance {
  std::string path;
  const TypeLayout* layout;
  SourceLoc loc;  ///< its component entry
  uint32_t first_var, first_param;
};

/// Where an equation or a when-clause of a layout comes from, for messages and instance records.
struct PartInfo {
  std::string text;  ///< as written; '\x01' stands for the instance's path and a dot
  SourceLoc loc;
  int32_t sub = -1;
  EquationOrigin origin = EquationOrigin::kComponent;
};

/// A type prepared for instantiation: its local names (a composite's include every part's, with
/// their relative paths), and templates of every equation, start value and parameter binding
/// over local indices. Prepared once per type; each instance copies the templates.
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

/// Composite types nest at most this deep (a model of a hundred levels is a mistake, and each
/// level copies the names below it).
constexpr size_t kMaxTypeDepth = 64;
/// One composite type holds at most this many variables with all its parts (a type is laid out
/// whole; twenty levels of two parts each would be a million components in one type; use count: in the model for big arrays).
constexpr double kMaxTypeVariables = 250000;

/// No connector slot: a composite's part, which the model's connections cannot reach.
constexpr uint32_t kNoSlot = UINT32_MAX;

/// Where one instance keeps a table's elements: consecutive parameters from `first`.
struct InstanceTable {
  ParamId first;
  uint32_t rows = 0, cols = 0;
  size_t flat_index = 0;  ///< its FlatSystem::tables entry
};

struct InstanceData {
  const TypeLayout* layout;
  VarId first_var;
  ParamId first_param;
  uint32_t first_slot;
};

struct ComponentArray {
  size_t spec_index;
  uint32_t first_instance;
  uint32_t count;
  bool is_array;
  uint32_t stride = 1;  ///< instance records per element: the component and a composite's parts
};

/// The model's components by name, for the connections and expressions that name them (two
/// look-ups per connection: 200 000 on a written-out model of 100 000 components). An
/// open-addressing table of (hash, entry) pairs over names held elsewhere (the spec's, which
/// outlive it): a look-up reads one slot and the name it finds, where a node-based map walked
/// a bucket, a node and its key (about 14 % of flattening the written-out chain).
class ComponentIndex {
 public:
  void Reserve(size_t n) {
    if (2 * n > slots_.size()) Rehash(2 * n);
  }
  /// The component named `name`, or null.
  const ComponentArray* Find(std::string_view name) const {
    if (slots_.empty()) return nullptr;
    const uint64_t hash = Hash(name);
    const size_t mask = slots_.size() - 1;
    for (size_t at = hash & mask;; at = (at + 1) & mask) {
      const uint64_t slot = slots_[at];
      if (slot == 0) return nullptr;
      const auto entry = static_cast<uint32_t>(slot) - 1;
      if (slot >> 32 == hash >> 32 && names_[entry] == name) return &entries_[entry];
    }
  }
  /// Adds a component whose name is not in the table yet; `name` must outlive the table.
  void Add(std::string_view name, const ComponentArray& entry) {
    if (2 * (entries_.size() + 1) > slots_.size()) Rehash(std::max<size_t>(64, 2 * slots_.size()));
    names_.push_back(name);
    entries_.push_back(entry);
    Place(Hash(name), static_cast<uint32_t>(entries_.size()));
  }

 private:
  static uint64_t Hash(std::string_view name) {
    // The high half tells names apart before they are compared; neither half is 0 for an entry.
    const uint64_t h = std::hash<std::string_view>()(name);
    return h | (uint64_t{1} << 32);
  }
  /// Stores entry number `number` (1-based: 0 is an empty slot) under `hash`.
  void Place(uint64_t hash, uint32_t number) {
    const size_t mask = slots_.size() - 1;
    size_t at = hash & mask;
    while (slots_[at] != 0) at = (at + 1) & mask;
    slots_[at] = (hash & ~uint64_t{0xffffffff}) | number;
  }
  void Rehash(size_t at_least) {
    size_t size = 64;
    while (size < at_least) size *= 2;
    slots_.assign(size, 0);
    for (uint32_t k = 0; k < entries_.size(); ++k) Place(Hash(names_[k]), k + 1);
  }

  std::vector<uint64_t> slots_;  ///< (hash's high half, entry number), 0 when empty; a power of 2
  std::vector<std::string_view> names_;
  std::vector<ComponentArray> entries_;
};

/// The classes of a union-find forest (`find` gives an element's root), each in element order,
/// the classes ordered by their first element.
template <class Find>
std::vector<std::vector<uint32_t>> Classes(size_t n, Find&& find) {
  std::vector<std::vector<uint32_t>> sets;
  std::vector<int32_t> set_of_root(n, -1);
  for (uint32_t k = 0; k < n; ++k) {
    uint32_t r = find(k);
    if (set_of_root[r] < 0) {
      set_of_root[r] = static_cast<int32_t>(sets.size());
      sets.emplace_back();
    }
    sets[set_of_root[r]].push_back(k);
  }
  return sets;
}

/// The equations a build leaves unmade for alias elimination (FlatSystem::deferred): copies of
/// sure-alias templates, and connection equations between two variables. Each is x = ±y + c or
/// x = c, which alias elimination removes without its expression.
class DeferredAliases final : public DeferredEquations {
 public:
  explicit DeferredAliases(std::shared_ptr<ExprPool> pool) : pool_(std::move(pool)) {}

  bool Form(uint32_t k, std::vector<std::pair<VarId, double>>* terms, double* offset) const override {
    if (k >= entries_.size() || entries_[k].kind == kMade) return false;
    const Entry& e = entries_[k];
    terms->clear();
    *offset = 0;
    switch (e.kind) {
      case kCopy: {
        const SureAlias& a = shapes_[e.shape].form;
        for (const auto& [local, c] : a.terms) terms->emplace_back(VarId(e.x + local), c);
        *offset = a.offset;
        break;
      }
      case kZero: terms->emplace_back(VarId(e.x), 1.0); break;
      case kEqual:
        terms->emplace_back(VarId(e.x), 1.0);
        terms->emplace_back(VarId(e.y), -1.0);
        break;
      case kSum:
        terms->emplace_back(VarId(e.x), 1.0);
        terms->emplace_back(VarId(e.y), 1.0);
        break;
      case kMade: break;
    }
    return true;
  }

  ExprId Make(uint32_t k) const override {
    ExprPool& p = *pool_;
    const Entry& e = entries_[k];
    if (e.kind == kCopy) return CopyTemplate(&p, *shapes_[e.shape].tmpl, VarId(e.x), ParamId(e.y), &scratch_, NoTable);
    // The leaves in the order Connections makes them.
    if (e.kind == kZero) return p.Var(VarId(e.x));
    if (e.kind == kEqual) {
      const ExprId y = p.Var(VarId(e.y));
      return p.Sub(p.Var(VarId(e.x)), y);
    }
    const ExprId x = p.Var(VarId(e.x));
    return p.Add(x, p.Var(VarId(e.y)));
  }

  /// A sure-alias template (`form` is ReadSureAlias's) whose copies AddCopy records.
  uint32_t AddShape(const Template& t, const SureAlias& form) {
    shapes_.push_back({&t, form});
    return static_cast<uint32_t>(shapes_.size() - 1);
  }
  /// Flat equation k is a copy of `shape` for the instance whose first variable and parameter
  /// are given.
  void AddCopy(size_t k, uint32_t shape, VarId first_var, ParamId first_param) {
    Set(k, {kCopy, shape, first_var.value(), first_param.value()});
  }
  /// Flat equation k is x = 0 (an unconnected flow), x = y or x + y = 0 (a connection).
  void AddZero(size_t k, VarId x) { Set(k, {kZero, 0, x.value(), 0}); }
  void AddEqual(size_t k, VarId x, VarId y) { Set(k, {kEqual, 0, x.value(), y.value()}); }
  void AddSum(size_t k, VarId x, VarId y) { Set(k, {kSum, 0, x.value(), y.value()}); }
  bool empty() const { return entries_.empty(); }
  /// Makes the deferred equations that name a variable `flat` now calls discrete (a model's
  /// when-clause assigns it, found after the components): alias elimination keeps those.
  void MakeDiscrete(FlatSystem* flat) {
    std::vector<std::pair<VarId, double>> terms;
    double offset = 0;
    for (uint32_t k = 0; k < entries_.size(); ++k) {
      if (!Form(k, &terms, &offset)) continue;
      const bool discrete = std::any_of(terms.begin(), terms.end(),
                                        [&](const auto& t) { return flat->variables[t.first.value()].discrete; });
      if (!discrete) continue;
      flat->equations[k].residual = Make(k);
      entries_[k].kind = kMade;
    }
  }
  /// Takes the type layouts, whose templates the copies read.
  void Keep(std::unordered_map<const ComponentType*, std::unique_ptr<TypeLayout>> layouts) {
    layouts_ = std::move(layouts);
  }

 private:
  enum Kind : uint8_t { kMade, kCopy, kZero, kEqual, kSum };
  struct Entry {
    Kind kind = kMade;
    uint32_t shape = 0;
    uint32_t x = 0, y = 0;  ///< a copy: its first variable and parameter; else the variables
  };
  void Set(size_t k, Entry e) {
    if (entries_.size() <= k) entries_.resize(k + 1);
    entries_[k] = e;
  }
  std::shared_ptr<ExprPool> pool_;
  std::vector<Entry> entries_;  ///< by flat equation
  struct Shape {
    const Template* tmpl;
    SureAlias form;
  };
  std::vector<Shape> shapes_;
  std::unordered_map<const ComponentType*, std::unique_ptr<TypeLayout>> layouts_;
  mutable std::vector<ExprId> scratch_;
};

/// No DeferredAliases shape: the equation's copies are made (Flattener::SureAliasShapes).
constexpr uint32_t kNotSure = UINT32_MAX;

class Flattener {
 public:
  Flattener(const ModelSpec& spec, const Library& library, const ParameterOverrides& overrides,
            bool defer_equations)
      : spec_(spec), library_(library), overrides_(overrides) {
    flat_.pool = std::make_shared<ExprPool>();
    if (defer_equations) deferred_ = std::make_shared<DeferredAliases>(flat_.pool);
    flat_.model_name = spec.name;
    flat_.file = spec.file;
    flat_.experiment = spec.experiment;
    for (const auto& d : spec.defines) {
      if (library.HasComponent(d.name)) {
        throw ModelError(d.loc, "type " + d.name +
                                    " has the name of a library component; choose another name");
      }
      if (const ComponentType* other = defines_->FindComponent(d.name)) {
        throw ModelError(d.loc, "type " + d.name + " is defined twice (also at " + other->loc.ToString() + ")");
      }
      defines_->AddComponent(d);
    }
  }

  FlatSystem Run() {
    ModelParameters();
    ModelVariables();
    Components();
    Connections();
    ModelEquations();
    Outputs();
    OrderParameters();
    CheckOverrides();
    flat_.defines = defines_;  // instances point into these types
    flat_.structural = structural_;
    if (deferred_ && !deferred_->empty()) {
      if (model_assigns_) deferred_->MakeDiscrete(&flat_);
      deferred_->Keep(std::move(layouts_));
      flat_.deferred = std::move(deferred_);
    }
    return std::move(flat_);
  }

 private:
  ExprPool& pool() { return *flat_.pool; }

  // -------------------------------------------------------------------------------------------
  // Model parameters and structural evaluation

  void ModelParameters() {
    for (const auto& p : spec_.parameters) {
      if (model_param_.count(p.name)) throw ModelError(p.loc, "parameter " + p.name + " is declared twice");
      FlatParameter fp;
      fp.name = flat_.Own(p.name);
      fp.type = p.type;
      if (p.min) fp.min = *p.min;
      if (p.max) fp.max = *p.max;
      fp.unit = flat_.Own(p.unit);
      fp.doc = flat_.Own(p.doc);
      fp.loc = p.loc;
      model_param_[p.name] = ParamId(flat_.parameters.size());
      flat_.parameters.push_back(fp);
    }
    for (size_t k = 0; k < spec_.parameters.size(); ++k) {
      const auto& p = spec_.parameters[k];
      flat_.parameters[k].binding = ModelExpr(*p.value, p.value_text, p.loc, nullptr, false);
    }
  }

  /// The numeric value of a model-scope expression at build time (count:, indices, ranges). Only
  /// model parameters may appear; their values (with overrides) are computed once.
  double StructuralValue(const Ast& a, const std::string& text, const SourceLoc& loc,
                         const std::pair<std::string, double>* loop) {
    ExprId e = ModelExpr(a, text, loc, loop, false);
    if (!pool().IsParamOnly(e)) throw ModelError(loc, "'" + text + "' must be a constant expression of parameters");
    if (pool().IsConst(e)) return pool().ConstValue(e);
    if (model_values_.empty() && !spec_.parameters.empty()) {
      model_values_.resize(spec_.parameters.size());
      for (size_t k = 0; k < spec_.parameters.size(); ++k) model_values_[k] = ModelParamValue(ParamId(k));
    }
    for (ExprId leaf : CollectLeaves(pool(), e, kHasParam)) {
      uint32_t id = pool().node(leaf).a;
      if (id >= spec_.parameters.size()) {
        throw ModelError(loc, "'" + text + "' shapes the model's structure, so it may use model parameters only");
      }
      structural_[flat_.ParameterName(ParamId(id))] = model_values_[id];
    }
    LeafValues lv;
    lv.params = model_values_.data();
    return Evaluate(pool(), e, lv);
  }

  /// A model parameter's value, following its binding through other model parameters (each
  /// evaluated once; a binding that reaches itself is a cycle).
  double ModelParamValue(ParamId id) {
    const size_t n = spec_.parameters.size();
    if (param_state_.size() != n) {
      param_state_.assign(n, 0);
      param_value_.assign(n, 0.0);
    }
    std::vector<std::pair<uint32_t, bool>> stack{{id.value(), false}};
    while (!stack.empty()) {
      auto [q, expanded] = stack.back();
      stack.pop_back();
      if (param_state_[q] == 2) continue;
      const FlatParameter& p = flat_.parameters[q];
      auto ov = overrides_.find(flat_.ParameterName(ParamId(q)));
      if (ov != overrides_.end()) {
        param_value_[q] = ov->second;
        param_state_[q] = 2;
        continue;
      }
      std::vector<ExprId> deps = CollectLeaves(pool(), p.binding, kHasParam);
      if (!expanded) {
        if (param_state_[q] == 1) {
          throw ModelError(p.loc, "the parameters' bindings form a cycle through " + flat_.ParameterName(ParamId(q)));
        }
        param_state_[q] = 1;
        stack.push_back({q, true});
        for (ExprId pe : deps) {
          uint32_t d = pool().node(pe).a;
          if (param_state_[d] == 1) {
            throw ModelError(flat_.parameters[d].loc,
                             "the parameters' bindings form a cycle through " + flat_.ParameterName(ParamId(d)));
          }
          if (param_state_[d] == 0) stack.push_back({d, false});
        }
        continue;
      }
      LeafValues lv;
      lv.params = param_value_.data();
      param_value_[q] = Evaluate(pool(), p.binding, lv);
      param_state_[q] = 2;
    }
    return param_value_[id.value()];
  }

  /// A structural value that must be a whole number (a count, an index, a range bound). It stays
  /// a double: callers compare it with their limits before converting it to an integer.
  double StructuralWhole(const Ast& a, const std::string& text, const SourceLoc& loc,
                         const std::pair<std::string, double>* loop, const std::string& what) {
    double v = StructuralValue(a, text, loc, loop);
    if (!std::isfinite(v) || v != std::floor(v)) {
      throw ModelError(loc, what + " must be a whole number, found " + NumberText(v));
    }
    return v;
  }

  // -------------------------------------------------------------------------------------------
  // Model-scope names: model parameters, model variables, instance paths, a loop index.

  const ComponentType* FindType(const std::string& name) const {
    if (const ComponentType* t = defines_->FindComponent(name)) return t;
    return library_.FindComponent(name);
  }

  /// Resolves `path` (a kName) in the model scope to a leaf expression.
  ExprId ModelName(const Ast& a, const SourceLoc& base, const std::pair<std::string, double>* loop,
                   bool allow_variables, const std::string& text) {
    SourceLoc loc = base.Shifted(a.column);
    const auto& first = a.path[0];
    if (a.path.size() == 1 && !first.index) {
      if (loop && first.name == loop->first) return pool().Const(loop->second);
      auto mp = model_param_.find(first.name);
      if (mp != model_param_.end()) return pool().Param(mp->second);
      auto mv = model_var_.find(first.name);
      if (mv != model_var_.end()) {
        if (!allow_variables) {
          throw ModelError(loc, "'" + first.name + "' is a variable; only parameters may be used in '" + text + "'");
        }
        return pool().Var(mv->second);
      }
      if (first.name == "time") {
        if (!allow_variables) throw ModelError(loc, "time cannot be used in '" + text + "'");
        return pool().Time();
      }
      if (first.name == "pi") return pool().Const(M_PI);
    }
    // An instance path: first segment is a component (or an element of an array).
    const ComponentArray* arr = arrays_.Find(first.name);
    if (!arr) {
      std::vector<std::string> names;
      for (const auto& p : spec_.parameters) names.push_back(p.name);
      for (const auto& c : spec_.components) names.push_back(c.name);
      for (const auto& v : spec_.variables) names.push_back(v.name);
      auto close = ClosestNames(first.name, names);
      throw ModelError(loc, "unknown name '" + a.PathText() + "' in '" + text + "'" +
                                (close.empty() ? "" : " (did you mean " + JoinNames(close) + "?)") +
                                " (valid names: " + JoinNames(names) + ")");
    }
    uint32_t inst = ElementOf(*arr, first, loc, loop, text);
    const InstanceData& data = instance_data_[inst];
    std::string local;
    for (size_t k = 1; k < a.path.size(); ++k) {
      if (k > 1) local += ".";
      local += a.path[k].name;
      if (a.path[k].index) {  // an element of a part array inside a composite: arm.links[2].phi
        double i = Index(*a.path[k].index, loc, loop);
        local += "[" + NumberText(i) + "]";
      }
    }
    if (local.empty()) throw ModelError(loc, "'" + a.PathText() + "' names a component, not one of its variables");
    auto v = data.layout->var_index.find(local);
    if (v != data.layout->var_index.end()) {
      if (!allow_variables) {
        throw ModelError(loc, "'" + a.PathText() + "' is a variable; only parameters may be used in '" + text + "'");
      }
      return pool().Var(VarId(data.first_var.value() + v->second));
    }
    auto p = data.layout->param_index.find(local);
    if (p != data.layout->param_index.end()) {
      return pool().Param(ParamId(data.first_param.value() + p->second));
    }
    auto names = data.layout->LocalNames();
    throw ModelError(loc, flat_.InstancePath(InstanceId(inst)) + " (" + data.layout->type->name +
                              ") has no variable or parameter '" + local + "' (valid names: " +
                              JoinNames(names) + ")");
  }

  /// The value of a subscript. A whole number, the loop index, or a sum of these is added up
  /// here, exactly (whole numbers below 2^52); anything else is built and evaluated as a structural
  /// value, whose text only a message needs (a for: connection resolves two subscripts per
  /// iteration).
  double Index(const Ast& a, const SourceLoc& loc, const std::pair<std::string, double>* loop) {
    if (std::optional<double> v = WholeSum(a, loop)) return *v;
    return StructuralWhole(a, AstToString(a), loc, loop, "an index");
  }

  static std::optional<double> WholeSum(const Ast& a, const std::pair<std::string, double>* loop) {
    constexpr double kExact = 4503599627370496.0;  // 2^52: sums of whole numbers below it are exact
    auto whole = [&](double x) -> std::optional<double> {
      if (x == std::floor(x) && std::fabs(x) < kExact) return x;
      return std::nullopt;
    };
    switch (a.kind) {
      case Ast::Kind::kNumber:
        return whole(a.number);
      case Ast::Kind::kName:
        if (loop && a.path.size() == 1 && !a.path[0].index && a.path[0].name == loop->first) return whole(loop->second);
        return std::nullopt;
      case Ast::Kind::kSum: {
        double r = 0;
        for (size_t k = 0; k < a.args.size(); ++k) {
          std::optional<double> x = WholeSum(*a.args[k], loop);
          if (!x) return std::nullopt;
          r += a.op[k] == '-' ? -*x : *x;
        }
        return whole(r);
      }
      default:
        return std::nullopt;
    }
  }

  uint32_t ElementOf(const ComponentArray& arr, const NameSegment& seg, const SourceLoc& loc,
                     const std::pair<std::string, double>* loop, const std::string& text) {
    if (!arr.is_array) {
      if (seg.index) throw ModelError(loc, seg.name + " is not an array (it has no count:), in '" + text + "'");
      return arr.first_instance;
    }
    if (!seg.index) {
      throw ModelError(loc, seg.name + " is an array of " + std::to_string(arr.count) +
                                " components; name one element, e.g. " + seg.name + "[1]");
    }
    double k = Index(*seg.index, loc, loop);
    if (k < 1 || k > arr.count) {
      throw ModelError(loc, seg.name + "[" + NumberText(k) + "] is out of range 1.." +
                                std::to_string(arr.count) + " in '" + text + "'");
    }
    return arr.first_instance + arr.stride * static_cast<uint32_t>(k - 1);
  }

  /// Builds an expression of the model scope.
  ExprId ModelExpr(const Ast& a, const std::string& text, const SourceLoc& loc,
                   const std::pair<std::string, double>* loop, bool allow_variables) {
    // A number (most modifiers' values) needs no walk and no text for messages.
    if (a.kind == Ast::Kind::kNumber || a.kind == Ast::Kind::kBool) return pool().Const(a.number);
    const std::string quoted = Excerpt(text, 0);  // messages quote the text
    return BuildExpr(a, quoted, loc, [&](const Ast& name) {
      return ModelName(name, loc, loop, allow_variables, quoted);
    }, allow_variables);
  }

  /// A start value of the model scope (a variable's or a modifier's): its text, which only
  /// messages quote, is made for an expression, not for a number (a start per written-out mass).
  ExprId StartExpr(const Ast& a, const SourceLoc& loc, const std::pair<std::string, double>* loop) {
    if (a.kind == Ast::Kind::kNumber || a.kind == Ast::Kind::kBool) return pool().Const(a.number);
    return ModelExpr(a, AstToString(a), loc, loop, false);
  }

  /// Expression building shared by the model scope; `name` resolves a kName node (a template
  /// parameter rather than a std::function: a modifier of an array is built once per element).
  template <class ResolveName>
  ExprId BuildExpr(const Ast& a, const std::string& text, const SourceLoc& loc, const ResolveName& name,
                   bool allow_variables) {
    ExprPool& p = pool();
    auto sub = [&](size_t k) { return BuildExpr(*a.args[k], text, loc, name, allow_variables); };
    switch (a.kind) {
      case Ast::Kind::kNumber:
      case Ast::Kind::kBool:
        return p.Const(a.number);
      case Ast::Kind::kName:
        return name(a);
      case Ast::Kind::kArray:
        throw ModelError(loc.Shifted(a.column), "an array where a number is expected, in '" + text + "'");
      case Ast::Kind::kUnary:
        return a.op == "not" ? p.Unary(Op::kNot, sub(0)) : p.Neg(sub(0));
      case Ast::Kind::kBinary:
      case Ast::Kind::kSum:
      case Ast::Kind::kProduct: {
        // A chain (a + b - c, a * b / c, a and b and c) as a balanced tree; relations and ^ have
        // two operands.
        std::vector<ExprId> operands;
        for (size_t k = 0; k < a.args.size(); ++k) operands.push_back(sub(k));
        return BuildChain(operands, ChainInverse(a), [&](ExprId x, bool inverse, ExprId y) {
          return p.Binary(ChainOp(a, inverse), x, y);
        });
      }
      case Ast::Kind::kIf: {
        // if c1 then v1 elseif c2 then v2 … else e, nested from the last branch.
        std::vector<ExprId> operands;
        for (size_t k = 0; k < a.args.size(); ++k) operands.push_back(sub(k));
        return BuildIfChain(operands, [&](ExprId c, ExprId x, ExprId y) { return p.If(c, x, y); });
      }
      case Ast::Kind::kCall: {
        Op op;
        if (FunctionOp(a.op, &op)) {
          return Arity(op) == 1 ? p.Unary(op, sub(0)) : p.Binary(op, sub(0), sub(1));
        }
        if (a.op == "noEvent") return p.NoEvent(sub(0));
        if (a.op == "interpolate" || a.op == "timeTable" || a.op == "booleanTable") {
          throw ModelError(loc.Shifted(a.column), a.op + "() reads a table of a component type, in its equations; the model's own " +
                                                      "equations cannot (use a CombiTimeTable, or a type with the table), in '" + text + "'");
        }
        if (!allow_variables) {
          throw ModelError(loc.Shifted(a.column), a.op + "() cannot be used in '" + text + "'");
        }
        if (a.op == "der") return TimeDerivative(&p, sub(0));
        if (a.op == "initial") return p.Initial();
        ExprId x = sub(0);
        if (p.op(x) != Op::kVar) {
          throw ModelError(loc.Shifted(a.column), a.op + "() takes a variable, in '" + text + "'");
        }
        ExprId pre = p.Pre(VarId(p.node(x).a));
        if (a.op == "pre") return pre;
        if (a.op == "edge") return p.Binary(Op::kAnd, x, p.Unary(Op::kNot, pre));
        if (a.op == "change") return p.Binary(Op::kNe, x, pre);
        throw ModelError(loc.Shifted(a.column), a.op + "() is not allowed in '" + text + "'");
      }
    }
    return p.Zero();
  }

  /// The operation of a kBinary, kSum or kProduct node; `inverse` for '-' and '/' operands.
  static Op ChainOp(const Ast& a, bool inverse) {
    if (a.kind == Ast::Kind::kSum) return inverse ? Op::kSub : Op::kAdd;
    if (a.kind == Ast::Kind::kProduct) return inverse ? Op::kDiv : Op::kMul;
    return BinaryOp(a.op);
  }

  /// Which operands of a kBinary, kSum or kProduct node enter through the inverse operator.
  static std::vector<bool> ChainInverse(const Ast& a) {
    if (a.kind == Ast::Kind::kBinary) return std::vector<bool>(a.args.size(), false);
    return InverseFlags(a.op);
  }

  static Op BinaryOp(const std::string& s) {
    static const std::unordered_map<std::string, Op> kOps = {
        {"+", Op::kAdd}, {"-", Op::kSub}, {"*", Op::kMul}, {"/", Op::kDiv}, {"^", Op::kPow},
        {"<", Op::kLt},  {"<=", Op::kLe}, {">", Op::kGt},  {">=", Op::kGe}, {"==", Op::kEq},
        {"<>", Op::kNe}, {"and", Op::kAnd}, {"or", Op::kOr}};
    return kOps.at(s);
  }

  static bool FunctionOp(const std::string& s, Op* op) {
    static const std::unordered_map<std::string, Op> kFns = {
        {"sin", Op::kSin},   {"cos", Op::kCos},   {"tan", Op::kTan},     {"asin", Op::kAsin},
        {"acos", Op::kAcos}, {"atan", Op::kAtan}, {"sinh", Op::kSinh},   {"cosh", Op::kCosh},
        {"tanh", Op::kTanh}, {"exp", Op::kExp},   {"log", Op::kLog},     {"log10", Op::kLog10},
        {"sqrt", Op::kSqrt}, {"abs", Op::kAbs},   {"sign", Op::kSign},   {"atan2", Op::kAtan2},
        {"min", Op::kMin},   {"max", Op::kMax}};
    auto it = kFns.find(s);
    if (it == kFns.end()) return false;
    *op = it->second;
    return true;
  }

  // -------------------------------------------------------------------------------------------
  // Component types: layouts and templates

  const TypeLayout& Layout(const ComponentType* type) {
    auto it = layouts_.find(type);
    if (it != layouts_.end()) return *it->second;
    for (size_t k = 0; k < laying_out_.size(); ++k) {
      if (laying_out_[k] != type) continue;
      std::string cycle;
      for (size_t j = k; j < laying_out_.size(); ++j) cycle += laying_out_[j]->name + " -> ";
      cycle += type->name;
      const ComponentSpec* at = current_component_;
      throw ModelError(at ? at->type_loc : type->loc,
                       "type " + type->name + " contains itself: " + cycle + "; a type cannot be a part of itself");
    }
    if (laying_out_.size() >= kMaxTypeDepth) {
      std::string chain;
      for (const ComponentType* t : laying_out_) chain += t->name + " -> ";
      const ComponentSpec* at = current_component_;
      throw ModelError(at ? at->type_loc : type->loc,
                       "types nested deeper than " + std::to_string(kMaxTypeDepth) + " levels: " + Excerpt(chain + type->name, 0) +
                           "; flatten the hierarchy");
    }
    laying_out_.push_back(type);
    auto layout = std::make_unique<TypeLayout>();
    TypeLayout& L = *layout;
    L.type = type;
    // Connector variables first, then declared variables.
    std::unordered_map<std::string, const VariableDecl*> declared;
    for (const auto& v : type->variables) {
      if (declared.count(v.name)) throw ModelError(v.loc, type->name + "." + v.name + " is declared twice");
      declared[v.name] = &v;
    }
    for (const auto& c : type->connectors) {
      const ConnectorType* ct = library_.FindConnector(c.type);
      if (!ct) {
        throw ModelError(c.loc, "unknown connector type '" + c.type + "' for " + type->name + "." +
                                    c.name + " (valid connector types: " +
                                    JoinNames(library_.ConnectorNames()) + ")");
      }
      if (L.connector_index.count(c.name)) throw ModelError(c.loc, type->name + "." + c.name + " is declared twice");
      L.connector_index[c.name] = static_cast<uint32_t>(L.connectors.size());
      L.connectors.push_back({&c, ct, static_cast<uint32_t>(L.vars.size())});
      if (ct->is_signal) {
        LocalVar lv;
        lv.name = c.name;
        lv.type = ct->signal_type;
        lv.is_input = ct->is_input;
        auto d = declared.find(c.name);
        if (d != declared.end()) {
          lv.decl = d->second;
          lv.unit = d->second->unit;
          declared.erase(d);
        }
        L.vars.push_back(lv);
      } else {
        for (const auto& pv : ct->potentials) {
          LocalVar lv;
          lv.name = c.name + "." + pv.name;
          lv.unit = pv.unit;
          L.vars.push_back(lv);
        }
        for (const auto& fv : ct->flows) {
          LocalVar lv;
          lv.name = c.name + "." + fv.name;
          lv.unit = fv.unit;
          lv.is_flow = true;
          L.vars.push_back(lv);
        }
      }
    }
    for (const auto& v : type->variables) {
      if (!declared.count(v.name)) continue;  // attributes of a signal connector
      if (L.connector_index.count(v.name)) throw ModelError(v.loc, type->name + "." + v.name + " is both a connector and a variable");
      LocalVar lv;
      lv.name = v.name;
      lv.decl = &v;
      lv.type = v.type;
      lv.unit = v.unit;
      L.vars.push_back(lv);
    }
    const size_t own_vars = L.vars.size();
    for (const auto& p : type->parameters) L.params.push_back({p.name, &p, -1, SourceLoc()});
    for (uint32_t k = 0; k < L.vars.size(); ++k) L.var_index[L.vars[k].name] = k;
    for (uint32_t k = 0; k < L.params.size(); ++k) {
      const auto& p = type->parameters[k];
      if (L.param_index.count(p.name) || L.var_index.count(p.name)) {
        throw ModelError(p.loc, type->name + "." + p.name + " is declared twice");
      }
      L.param_index[p.name] = k;
    }
    for (const auto& d : type->tables) {
      if (L.param_index.count(d.name) || L.var_index.count(d.name) || L.table_index.count(d.name)) {
        throw ModelError(d.loc, type->name + "." + d.name + " is declared twice");
      }
      L.table_index[d.name] = static_cast<uint32_t>(L.tables.size());
      L.tables.push_back({&d, 0, 0, {}});
    }
    for (const ConnectorSlot& cs : L.connectors) CheckCondition(L, *cs.decl);
    // A composite's parts: their names first, so that every expression of the type can use them
    // (mass.s, spring.c); their templates after the type's own.
    std::vector<PartPlan> parts = LayoutPartNames(&L);
    // Templates.
    for (const auto& p : type->parameters) {
      L.param_defaults.push_back(MakeTemplate(L, *p.value, p.value_text, p.loc, true));
    }
    for (TypeLayout::TableSlot& slot : L.tables) {
      const ParameterDecl& d = *slot.decl;
      for (const AstPtr& e : TableElements(d.value, d, d.loc, type->name + "." + d.name, &slot.rows, &slot.cols)) {
        slot.defaults.push_back(MakeTemplate(L, *e, d.value_text, d.loc, true));
      }
    }
    for (size_t k = 0; k < own_vars; ++k) {
      const LocalVar& v = L.vars[k];
      L.starts.push_back(v.decl && v.decl->start
                             ? MakeTemplate(L, *v.decl->start, AstToString(*v.decl->start), v.decl->loc, true)
                             : Template());
    }
    for (const auto& e : type->equations) {
      L.equations.push_back(EquationTemplate(L, e));
      L.equation_info.push_back({e.text, e.loc, -1, EquationOrigin::kComponent});
    }
    for (const auto& e : type->initial_equations) {
      L.initial_equations.push_back(EquationTemplate(L, e));
      L.initial_info.push_back({e.text, e.loc, -1, EquationOrigin::kInitial});
    }
    // Discrete variables: Boolean and Integer ones, and those a when-clause or impact assigns.
    L.discrete.assign(L.vars.size(), false);
    for (size_t k = 0; k < L.vars.size(); ++k) L.discrete[k] = L.vars[k].type != ValueType::kReal;
    for (const PartPlan& pl : parts) {  // a part's own discrete variables
      const uint32_t vo = L.subs[pl.sub].first_var;
      for (size_t k = 0; k < pl.layout->vars.size(); ++k) L.discrete[vo + k] = pl.layout->discrete[k];
    }
    auto local_var = [&](const std::string& name, const SourceLoc& loc, const std::string& what) {
      auto found = L.var_index.find(name);
      if (found == L.var_index.end()) {
        throw ModelError(loc, "unknown variable '" + name + "' in " + what + " of " + type->name +
                                  " (valid variables: " + JoinNames([&] {
                                    std::vector<std::string> v;
                                    for (const auto& x : L.vars) v.push_back(x.name);
                                    return v;
                                  }()) + ")");
      }
      return found->second;
    };
    for (const auto& w : type->whens) {
      TypeLayout::WhenTemplate wt;
      wt.condition = MakeTemplate(L, *w.condition, w.text, w.loc, false);
      for (const auto& st : w.statements) {
        uint32_t target = local_var(st.target, st.loc, "'" + st.text + "'");
        Template value = MakeTemplate(L, *st.value, st.text, st.loc, false);
        if (st.is_reinit) {
          wt.reinits.emplace_back(target, std::move(value));
        } else {
          wt.assigns.emplace_back(target, std::move(value));
          L.discrete[target] = true;
        }
      }
      L.whens.push_back(std::move(wt));
      L.when_info.push_back({w.text, w.loc, -1, EquationOrigin::kComponent});
    }
    for (const auto& im : type->impacts) {
      TypeLayout::ImpactTemplate tmpl;
      tmpl.gap = MakeTemplate(L, *im.gap, im.gap_text, im.loc, false);
      tmpl.velocity = MakeTemplate(L, *im.velocity, im.velocity_text, im.loc, false);
      tmpl.restitution = MakeTemplate(L, *im.restitution, im.restitution_text, im.loc, true);
      tmpl.v_small = MakeTemplate(L, *im.v_small, im.v_small_text, im.loc, true);
      tmpl.release = MakeTemplate(L, *im.release, im.release_text, im.loc, false);
      tmpl.force = local_var(im.force, im.loc, "impact");
      tmpl.contact = local_var(im.contact, im.loc, "impact");
      tmpl.decl = &im;
      if (L.vars[tmpl.contact].type != ValueType::kBoolean) {
        throw ModelError(im.loc, "the impact contact of " + type->name + " must be a Boolean variable (type: Boolean)");
      }
      L.discrete[tmpl.contact] = true;
      L.impacts.push_back(std::move(tmpl));
    }
    CheckTypeUnits(L);
    LayoutPartTemplates(&L, parts);
    InnerConnections(&L, parts);
    CheckLocalBalance(L);
    laying_out_.pop_back();
    const TypeLayout& ref = *layout;
    layouts_[type] = std::move(layout);
    return ref;
  }

  /// The dimension check of a type's own equations (core/lang/unit_check.h), once per type.
  static void CheckTypeUnits(const TypeLayout& L) {
    CheckComponentUnits(*L.type, [&L](const std::string& name) -> std::string {
      if (auto v = L.var_index.find(name); v != L.var_index.end()) return L.vars[v->second].unit;
      if (auto p = L.param_index.find(name); p != L.param_index.end()) {
        return L.params[p->second].decl ? L.params[p->second].decl->unit : std::string();
      }
      return std::string();
    });
  }

  // -------------------------------------------------------------------------------------------
  // Composite types: parts laid out inside the layout of the type that holds them

  /// One element of a part of a composite (a component, or one element of a `count:` array).
  struct PartPlan {
    const ComponentSpec* spec;
    const TypeLayout* layout;
    std::string path;      ///< relative to the composite: "mass", "links[2]"
    int32_t sub;           ///< its index in the composite's subs
    int32_t sub_base;      ///< where its own subs start in the composite's subs
    double index;          ///< 1-based element index (the modifiers' i), 0 for a single part
    uint32_t first_slot;   ///< its first connector in InnerConnections' slot list
  };

  /// Appends every part's variables and parameters (and those of its parts) to L under their
  /// relative paths, and returns the parts in order.
  std::vector<PartPlan> LayoutPartNames(TypeLayout* Lp) {
    TypeLayout& L = *Lp;
    const ComponentType* type = L.type;
    std::vector<PartPlan> plans;
    std::unordered_set<std::string> names;
    double layout_bytes = 0;
    for (const auto& c : type->components) {
      if (!names.insert(c.name).second || L.var_index.count(c.name) || L.param_index.count(c.name) ||
          L.connector_index.count(c.name)) {
        throw ModelError(c.loc, "the name " + c.name + " is used twice in " + type->name);
      }
      const ComponentType* part_type = FindType(c.type);
      if (!part_type) UnknownType(c);
      const ComponentSpec* saved = current_component_;
      current_component_ = &c;
      const TypeLayout& S = Layout(part_type);
      if (!S.tables.empty()) {
        throw ModelError(c.loc, c.name + " (" + c.type + ") in " + type->name + " has the table " +
                                    S.tables[0].decl->name + "; a part of a composite type cannot have a table yet " +
                                    "(use the component in the model)");
      }
      uint32_t n = c.count ? PartCount(c, L, S) : 1;
      // The type's parts so far, and these, must fit in the memory budget before they are laid out
      // (parts of parts multiply: twenty levels of two parts each are a million components).
      layout_bytes += n * EstimatedBytes(S);
      CheckLayoutBudget(c, L, layout_bytes);
      if (static_cast<double>(L.vars.size()) + n * static_cast<double>(S.vars.size()) > kMaxTypeVariables) {
        throw ModelError(c.loc, L.type->name + " with its parts up to " + c.name + " (" + c.type + ") has more than " +
                                    std::to_string(static_cast<long>(kMaxTypeVariables)) + " variables; parts of parts multiply: " +
                                    "make large arrays with count: in the model");
      }
      current_component_ = saved;
      for (uint32_t k = 0; k < n; ++k) {
        PartPlan pl;
        pl.spec = &c;
        pl.layout = &S;
        pl.path = c.count ? c.name + "[" + std::to_string(k + 1) + "]" : c.name;
        pl.index = c.count ? k + 1.0 : 0.0;
        pl.first_slot = 0;
        const auto var_off = static_cast<uint32_t>(L.vars.size());
        const auto param_off = static_cast<uint32_t>(L.params.size());
        pl.sub = static_cast<int32_t>(L.subs.size());
        L.subs.push_back({pl.path, &S, c.loc, var_off, param_off});
        pl.sub_base = static_cast<int32_t>(L.subs.size());
        for (const SubInstance& ss : S.subs) {
          L.subs.push_back({pl.path + "." + ss.path, ss.layout, ss.loc, var_off + ss.first_var, param_off + ss.first_param});
        }
        auto remap = [&](int32_t sub) { return sub < 0 ? pl.sub : pl.sub_base + sub; };
        // The part's variables and parameters under their paths in the composite.
        auto adopt = [&](const auto& items, auto* out, auto* index) {
          for (const auto& item : items) {
            auto local = item;
            local.name = pl.path + "." + item.name;
            local.sub = remap(item.sub);
            if (L.var_index.count(local.name) || L.param_index.count(local.name)) {
              throw ModelError(c.loc, "the name " + local.name + " in " + type->name + " is used twice");
            }
            (*index)[local.name] = static_cast<uint32_t>(out->size());
            out->push_back(std::move(local));
          }
        };
        adopt(S.vars, &L.vars, &L.var_index);
        adopt(S.params, &L.params, &L.param_index);
        for (const auto& [var, at] : S.connected) L.connected.emplace(var_off + var, at);
        plans.push_back(std::move(pl));
      }
    }
    return plans;
  }

  /// A conditional connector's `condition:` names a Boolean parameter of its type; a type with
  /// parts cannot make its own connectors conditional (its inner connections would name them).
  void CheckCondition(const TypeLayout& L, const ConnectorDecl& c) {
    if (c.condition.empty()) return;
    const ComponentType* type = L.type;
    auto p = L.param_index.find(c.condition);
    if (p == L.param_index.end() || type->parameters[p->second].type != ValueType::kBoolean) {
      std::vector<std::string> booleans;
      for (const auto& q : type->parameters) {
        if (q.type == ValueType::kBoolean) booleans.push_back(q.name);
      }
      throw ModelError(c.loc, "the condition of connector " + type->name + "." + c.name + " must be a Boolean " +
                                  "parameter of " + type->name + ", found '" + c.condition + "'" +
                                  (p == L.param_index.end() ? "" : " (a " + std::string(ValueTypeName(type->parameters[p->second].type)) + " parameter)") +
                                  " (Boolean parameters: " + (booleans.empty() ? std::string("none") : JoinNames(booleans)) + ")");
    }
    if (!type->components.empty()) {
      throw ModelError(c.loc, "connector " + type->name + "." + c.name + " of a type with parts cannot be conditional; " +
                                  "make the part's connector conditional instead");
    }
  }

  /// The count of an array part: a whole number written in the type (its structure is fixed;
  /// the type's parameters cannot size it), checked against the memory budget.
  uint32_t PartCount(const ComponentSpec& c, const TypeLayout& L, const TypeLayout& S) {
    std::string text = AstToString(*c.count);
    std::string what = "count of " + c.name + " in " + L.type->name;
    std::optional<double> n = ConstantValue(*c.count, nullptr);
    if (!n) {
      throw ModelError(c.loc, what + " must be a number: a type's structure is fixed, so its parameters cannot size its parts, found '" + text + "'");
    }
    return CheckedCount(c, S, *n, what, text);
  }

  void CheckLayoutBudget(const ComponentSpec& c, const TypeLayout& L, double bytes) {
    if (!budget_) budget_ = BuildMemoryBudget();
    if (planned_bytes_ + bytes <= budget_->bytes) return;
    throw ModelError(c.loc, L.type->name + " with its parts up to " + c.name + " (" + c.type + ") needs about " +
                                ByteText(planned_bytes_ + bytes) + " of memory to build, more than the budget of " +
                                ByteText(budget_->bytes) + " (" + budget_->source + "); parts of parts multiply");
  }

  /// The parts' templates, rebased to the composite's local indices, with the composite's
  /// modifiers (expressions of its own names) in place of the parts' defaults.
  void LayoutPartTemplates(TypeLayout* Lp, const std::vector<PartPlan>& plans) {
    TypeLayout& L = *Lp;
    for (const PartPlan& pl : plans) {
      const TypeLayout& S = *pl.layout;
      const uint32_t vo = L.subs[pl.sub].first_var, po = L.subs[pl.sub].first_param;
      auto rebase = [&](const Template& t) { return Rebased(t, vo, po); };
      auto remap = [&](const PartInfo& info) {
        PartInfo r = info;
        r.sub = info.sub < 0 ? pl.sub : pl.sub_base + info.sub;
        // Connection texts name connectors relative to the part: insert the part's path.
        for (size_t at = r.text.find('\x01'); at != std::string::npos; at = r.text.find('\x01', at + 1)) {
          r.text.insert(at + 1, pl.path + ".");
        }
        return r;
      };
      for (const Template& t : S.param_defaults) L.param_defaults.push_back(rebase(t));
      for (const Template& t : S.starts) L.starts.push_back(t.root >= 0 ? rebase(t) : Template());
      for (size_t k = 0; k < S.equations.size(); ++k) {
        L.equations.push_back(rebase(S.equations[k]));
        L.equation_info.push_back(remap(S.equation_info[k]));
      }
      for (size_t k = 0; k < S.initial_equations.size(); ++k) {
        L.initial_equations.push_back(rebase(S.initial_equations[k]));
        L.initial_info.push_back(remap(S.initial_info[k]));
      }
      for (size_t k = 0; k < S.whens.size(); ++k) {
        const auto& w = S.whens[k];
        TypeLayout::WhenTemplate wt;
        wt.condition = rebase(w.condition);
        for (const auto& [target, value] : w.assigns) wt.assigns.emplace_back(target + vo, rebase(value));
        for (const auto& [target, value] : w.reinits) wt.reinits.emplace_back(target + vo, rebase(value));
        L.whens.push_back(std::move(wt));
        L.when_info.push_back(remap(S.when_info[k]));
      }
      for (const auto& im : S.impacts) {
        TypeLayout::ImpactTemplate t;
        t.gap = rebase(im.gap);
        t.velocity = rebase(im.velocity);
        t.restitution = rebase(im.restitution);
        t.v_small = rebase(im.v_small);
        t.release = rebase(im.release);
        t.force = im.force + vo;
        t.contact = im.contact + vo;
        t.decl = im.decl;
        t.sub = im.sub < 0 ? pl.sub : pl.sub_base + im.sub;
        L.impacts.push_back(std::move(t));
      }
      // The composite's modifiers of this part.
      std::pair<std::string, double> index{"i", pl.index};
      template_loop_ = pl.index > 0 ? &index : nullptr;
      for (const Modifier& m : pl.spec->modifiers) {
        auto [is_param, k] = ModifierTarget(*pl.spec, S, m);
        if (is_param) {
          const AstPtr value = ModifierValue(m, *S.params[k].decl, pl.spec->name);
          L.param_defaults[po + k] = MakeTemplate(L, *value, m.value_text, m.loc, true);
          L.params[po + k].loc = m.loc;
        } else {
          if (m.start) L.starts[vo + k] = MakeTemplate(L, *m.start, AstToString(*m.start), m.loc, true);
          if (m.fixed) L.vars[vo + k].fixed = *m.fixed;
          if (m.state_priority) L.vars[vo + k].state_priority = *m.state_priority;
          L.vars[vo + k].loc = m.loc;
        }
      }
      template_loop_ = nullptr;
    }
  }

  /// A parameter modifier's value; one written with a unit (`m: 40 kg`) converted to the
  /// parameter's declared unit.
  static AstPtr ModifierValue(const Modifier& m, const ParameterDecl& target, const std::string& component) {
    if (m.value_unit.empty()) return m.value;
    return ValueInUnit(m.value->number, m.value_unit, target.unit, component + "." + target.name, m.loc);
  }

  /// Which parameter (first = true) or variable of `S` a modifier of component `c` sets.
  std::pair<bool, uint32_t> ModifierTarget(const ComponentSpec& c, const TypeLayout& S, const Modifier& m) {
    auto p = S.param_index.find(m.key);
    if (p != S.param_index.end()) {
      if (!m.value) throw ModelError(m.loc, c.name + "." + m.key + " is a parameter: give it a value, e.g. " + m.key + ": 2");
      return {true, p->second};
    }
    auto v = S.var_index.find(m.key);
    if (v != S.var_index.end()) {
      if (m.value) {
        throw ModelError(m.loc, c.name + "." + m.key + " is a variable: give its start value as " + m.key +
                                    ": {start: " + m.value_text + ", fixed: true}");
      }
      return {false, v->second};
    }
    std::vector<std::string> names;
    for (const auto& p2 : S.params) names.push_back(p2.name);
    for (const auto& v2 : S.vars) names.push_back(v2.name);
    auto close = ClosestNames(m.key, names);
    throw ModelError(m.key_loc, "unknown key '" + m.key + "' for " + c.name + " (" + S.type->name + ")" +
                                    (close.empty() ? "" : " (did you mean " + JoinNames(close) + "?)") +
                                    " (valid parameters and variables: " + JoinNames(names) +
                                    "; reserved keys: type, count, doc)");
  }

  /// A template with its local variables and parameters moved by the given offsets.
  static Template Rebased(const Template& t, uint32_t var_offset, uint32_t param_offset) {
    Template r;
    r.nodes = t.nodes;
    r.root = t.root;
    for (TNode& n : r.nodes) {
      if (n.kind == TNode::kLocalVar || n.kind == TNode::kPre) n.local += var_offset;
      if (n.kind == TNode::kLocalParam) n.local += param_offset;
    }
    return r;
  }

  /// The value of an expression of numbers and the loop index (a part's count, an index inside
  /// a type, a range bound inside a type); nothing when it uses any other name.
  static std::optional<double> ConstantValue(const Ast& a, const std::pair<std::string, double>* loop) {
    switch (a.kind) {
      case Ast::Kind::kNumber:
        return a.number;
      case Ast::Kind::kName:
        if (loop && a.path.size() == 1 && !a.path[0].index && a.path[0].name == loop->first) return loop->second;
        return std::nullopt;
      case Ast::Kind::kUnary: {
        if (a.op != "-") return std::nullopt;
        auto x = ConstantValue(*a.args[0], loop);
        if (!x) return std::nullopt;
        return -*x;
      }
      case Ast::Kind::kSum:
      case Ast::Kind::kProduct: {
        std::vector<bool> inverse = InverseFlags(a.op);
        double r = a.kind == Ast::Kind::kSum ? 0 : 1;
        for (size_t k = 0; k < a.args.size(); ++k) {
          auto x = ConstantValue(*a.args[k], loop);
          if (!x) return std::nullopt;
          if (a.kind == Ast::Kind::kSum) {
            r += inverse[k] ? -*x : *x;
          } else {
            r = inverse[k] ? r / *x : r * *x;
          }
        }
        return r;
      }
      default:
        return std::nullopt;
    }
  }

  /// The local name a dotted path inside a type stands for, subscripts evaluated: links[2].phi.
  std::string LocalPath(const Ast& a, const SourceLoc& loc, const std::string& text) {
    std::string local;
    for (size_t k = 0; k < a.path.size(); ++k) {
      if (k) local += ".";
      local += a.path[k].name;
      if (!a.path[k].index) continue;
      std::optional<double> i = ConstantValue(*a.path[k].index, template_loop_);
      if (!i || !std::isfinite(*i) || *i != std::floor(*i)) {
        throw ModelError(loc.Shifted(a.column), "a subscript inside a type must be a whole number (or the index i of an array part), in '" + text + "'");
      }
      local += "[" + NumberText(*i) + "]";
    }
    return local;
  }

  /// The connection sets inside a composite: its parts' connectors (inside) and its own
  /// (outside, named alone). Potentials are equal; the flows of inside connectors less those of
  /// outside ones sum to zero (Modelica's rule); an inside connector connected to nothing has zero
  /// flows; a signal set has exactly one driver (an inside output or an outside input).
  void InnerConnections(TypeLayout* Lp, std::vector<PartPlan>& plans) {
    TypeLayout& L = *Lp;
    const ComponentType* type = L.type;
    if (plans.empty() && type->connections.empty()) return;
    struct Slot {
      const ConnectorSlot* cs;
      uint32_t first_var;
      bool outside;
      std::string name;  ///< relative to the composite
      SourceLoc loc;     ///< the part's entry, or the connector's declaration
    };
    std::vector<Slot> slots;
    for (const ConnectorSlot& cs : L.connectors) slots.push_back({&cs, cs.first_local_var, true, cs.decl->name, cs.decl->loc});
    std::unordered_map<std::string, std::vector<size_t>> plans_of;  // part name -> its elements
    for (size_t k = 0; k < plans.size(); ++k) {
      PartPlan& pl = plans[k];
      plans_of[pl.spec->name].push_back(k);
      pl.first_slot = static_cast<uint32_t>(slots.size());
      const uint32_t vo = L.subs[pl.sub].first_var;
      for (const ConnectorSlot& cs : pl.layout->connectors) {
        slots.push_back({&cs, vo + cs.first_local_var, false, pl.path + "." + cs.decl->name, pl.spec->loc});
      }
    }
    std::vector<uint32_t> parent(slots.size());
    for (uint32_t k = 0; k < parent.size(); ++k) parent[k] = k;
    auto find = [&](uint32_t x) {
      while (parent[x] != x) x = parent[x] = parent[parent[x]];
      return x;
    };
    std::vector<SourceLoc> slot_loc(slots.size());
    auto resolve = [&](const Ast& a, const std::string& text, const SourceLoc& loc,
                       const std::pair<std::string, double>* loop) -> uint32_t {
      if (a.path.size() == 1 && !a.path[0].index) {
        auto c = L.connector_index.find(a.path[0].name);
        if (c != L.connector_index.end()) return c->second;
      }
      if (a.path.size() == 2 && !a.path[1].index) {
        auto part = plans_of.find(a.path[0].name);
        if (part != plans_of.end()) {
          const std::vector<size_t>& elems = part->second;
          const PartPlan& first = plans[elems[0]];
          size_t e = 0;
          if (first.spec->count) {
            if (!a.path[0].index) {
              throw ModelError(loc, a.path[0].name + " is an array of " + std::to_string(elems.size()) +
                                        " parts; name one element, e.g. " + a.path[0].name + "[1], in '" + text + "'");
            }
            std::optional<double> i = ConstantValue(*a.path[0].index, loop);
            if (!i || *i != std::floor(*i) || *i < 1 || *i > static_cast<double>(elems.size())) {
              throw ModelError(loc, "'" + text + "': the index must be a whole number in 1.." + std::to_string(elems.size()));
            }
            e = static_cast<size_t>(*i - 1);
          } else if (a.path[0].index) {
            throw ModelError(loc, a.path[0].name + " is not an array (it has no count:), in '" + text + "'");
          }
          const PartPlan& pl = plans[elems[e]];
          auto c = pl.layout->connector_index.find(a.path[1].name);
          if (c != pl.layout->connector_index.end()) return pl.first_slot + c->second;
        }
      }
      std::vector<std::string> names;
      for (const Slot& s : slots) names.push_back(s.name);
      auto close = ClosestNames(a.PathText(), names);
      throw ModelError(loc, "unknown connector '" + a.PathText() + "' in connection end '" + text + "' of " +
                                type->name + (close.empty() ? "" : " (did you mean " + JoinNames(close) + "?)") +
                                " (its own connectors are named alone, its parts' like mass.flange_a; valid: " +
                                JoinNames(names) + ")");
    };
    auto join = [&](uint32_t x, uint32_t y, const std::string& xt, const std::string& yt, const SourceLoc& loc) {
      CheckCompatible(slots[x].cs->type, xt, slots[y].cs->type, yt, loc, " in " + type->name);
      if (x == y) throw ModelError(loc, "connection of " + xt + " to itself");
      if (!slot_loc[x].known()) slot_loc[x] = loc;
      if (!slot_loc[y].known()) slot_loc[y] = loc;
      for (uint32_t s : {x, y}) {
        if (!slots[s].outside) L.connected.emplace(slots[s].first_var, loc);
      }
      parent[find(x)] = find(y);
    };
    for (const auto& c : type->connections) {
      auto one = [&](const std::pair<std::string, double>* loop) {
        join(resolve(*c.EndA(), c.a_text, c.a_loc, loop), resolve(*c.EndB(), c.b_text, c.b_loc, loop), c.a_text, c.b_text, c.a_loc);
      };
      if (c.loop_var.empty()) {
        one(nullptr);
        continue;
      }
      std::optional<double> from = ConstantValue(*c.loop_from, nullptr), to = ConstantValue(*c.loop_to, nullptr);
      const SourceLoc& loc = c.loop_loc.known() ? c.loop_loc : c.loc;
      // Whole numbers that doubles count exactly (beyond 2^53, i + 1 == i).
      constexpr double kExact = 9007199254740992.0;
      if (!from || !to || *from != std::floor(*from) || *to != std::floor(*to) || std::fabs(*from) > kExact ||
          std::fabs(*to) > kExact) {
        throw ModelError(loc, "the range of 'for: " + c.loop_text + "' inside " + type->name +
                                  " must have whole-number bounds below 2^53 (a type's structure is fixed)");
      }
      const double n = *to - *from + 1;
      if (n > static_cast<double>(slots.size())) {
        throw ModelError(loc, "the range of 'for: " + c.loop_text + "' makes more connections than " + type->name +
                                  " has connectors");
      }
      for (size_t k = 0; n > 0 && k < static_cast<size_t>(n); ++k) {
        std::pair<std::string, double> loop{c.loop_var, *from + static_cast<double>(k)};
        one(&loop);
      }
    }
    const std::vector<std::vector<uint32_t>> sets = Classes(slots.size(), find);
    auto add = [&](std::vector<std::pair<uint32_t, bool>> terms, std::string text, const SourceLoc& loc,
                   EquationOrigin origin) {
      L.equations.push_back(SignedSum(terms));
      L.equation_info.push_back({std::move(text), loc, -1, origin});
    };
    auto named = [&](uint32_t slot) { return "\x01" + slots[slot].name; };
    for (const auto& set : sets) {
      const Slot& s0 = slots[set[0]];
      const ConnectorType* ct = s0.cs->type;
      SourceLoc loc;
      for (uint32_t s : set) {
        if (slot_loc[s].known()) {
          loc = slot_loc[s];
          break;
        }
      }
      if (ct->is_signal) {
        std::vector<uint32_t> drivers;
        for (uint32_t s : set) {
          if (slots[s].cs->type->is_input == slots[s].outside) drivers.push_back(s);
        }
        if (set.size() == 1) {
          if (!s0.outside && ct->is_input && s0.cs->decl->condition.empty()) {
            throw ModelError(s0.loc, "the signal input " + s0.name + " inside " + type->name +
                                 " is connected to nothing; connect it to an output or to an input of " + type->name);
          }
          continue;
        }
        std::string members;
        for (uint32_t s : set) members += (members.empty() ? "" : ", ") + slots[s].name;
        if (drivers.size() != 1) {
          throw ModelError(loc, "the signals " + members + " inside " + type->name + " have " +
                                    std::to_string(drivers.size()) + " drivers; a signal set has exactly one " +
                                    "(an output of a part, or an input of " + type->name + ")");
        }
        for (uint32_t s : set) {
          if (s == drivers[0]) continue;
          add({{slots[s].first_var, false}, {slots[drivers[0]].first_var, true}},
              named(s) + " = " + named(drivers[0]) + " (connection)", loc, EquationOrigin::kConnection);
        }
        continue;
      }
      const auto np = static_cast<uint32_t>(ct->potentials.size());
      if (set.size() == 1) {
        if (s0.outside) continue;  // the type's own equations determine its own connector's flows
        for (uint32_t k = 0; k < ct->flows.size(); ++k) {
          add({{s0.first_var + np + k, false}}, named(set[0]) + "." + ct->flows[k].name + " = 0 (unconnected)",
              s0.loc, EquationOrigin::kUnconnectedFlow);
        }
        continue;
      }
      std::string members;
      for (uint32_t s : set) members += (members.empty() ? "" : ", ") + named(s);
      for (uint32_t k = 0; k < np; ++k) {
        for (size_t j = 1; j < set.size(); ++j) {
          add({{slots[set[j]].first_var + k, false}, {s0.first_var + k, true}},
              named(set[j]) + "." + ct->potentials[k].name + " = " + named(set[0]) + "." + ct->potentials[k].name +
                  " (connection)",
              loc, EquationOrigin::kConnection);
        }
      }
      for (uint32_t k = 0; k < ct->flows.size(); ++k) {
        std::vector<std::pair<uint32_t, bool>> terms;
        for (uint32_t s : set) terms.push_back({slots[s].first_var + np + k, slots[s].outside});
        bool any_outside = false;
        for (uint32_t s : set) any_outside = any_outside || slots[s].outside;
        add(terms, "sum of " + ct->flows[k].name + " over {" + members + "} = 0 (connection" +
                       (any_outside ? "; " + type->name + "'s own connectors count negative)" : ")"),
            loc, EquationOrigin::kConnection);
      }
    }
  }

  /// sum of ±local variables, as a template.
  static Template SignedSum(const std::vector<std::pair<uint32_t, bool>>& terms) {
    Template t;
    for (const auto& [local, negative] : terms) {
      TNode v;
      v.kind = TNode::kLocalVar;
      v.local = local;
      t.nodes.push_back(v);
      int32_t id = static_cast<int32_t>(t.nodes.size() - 1);
      if (t.root < 0) {
        if (negative) {
          TNode neg;
          neg.kind = TNode::kOp;
          neg.op = Op::kNeg;
          neg.a = id;
          t.nodes.push_back(neg);
          id = static_cast<int32_t>(t.nodes.size() - 1);
        }
        t.root = id;
        continue;
      }
      TNode op;
      op.kind = TNode::kOp;
      op.op = negative ? Op::kSub : Op::kAdd;
      op.a = t.root;
      op.b = id;
      t.nodes.push_back(op);
      t.root = static_cast<int32_t>(t.nodes.size() - 1);
    }
    return t;
  }

  /// Two connectors may be joined when they are of one type, or both signals of one value type.
  static bool Compatible(const ConnectorType* a, const ConnectorType* b) {
    return a == b || (a->is_signal && b->is_signal && a->signal_type == b->signal_type);
  }

  static void CheckCompatible(const ConnectorType* a, const std::string& a_text, const ConnectorType* b,
                              const std::string& b_text, const SourceLoc& loc, const std::string& where = "") {
    if (!Compatible(a, b)) {
      auto last = [](const std::string& n) { return n.substr(n.rfind('.') + 1); };
      std::string hint;
      if (last(a->name) == last(b->name)) {
        hint = " (flanges of two domains: a library type written without its package, such as Spring or "
               "Fixed, is the translational one; write the package for another domain's, such as "
               "Rotational.Spring)";
      }
      throw ModelError(loc, "cannot connect " + a_text + " (" + a->name + ") to " + b_text + " (" + b->name +
                                ")" + where + ": connectors of different kinds" + hint);
    }
  }

  /// Modelica's local balance: a component determines its own unknowns except the flow
  /// variables of its connectors (the connections determine those) and its signal inputs; the
  /// variables set by when-clauses and impacts need no equation.
  void CheckLocalBalance(const TypeLayout& L) {
    const ComponentType* type = L.type;
    // Only the type's own connectors' flows and own inputs are left to the outside; a part's
    // flows and inputs are the type's unknowns, which its connections determine.
    auto outside = [&](const LocalVar& v) { return v.sub < 0 && (v.is_flow || v.is_input); };
    size_t unknowns = 0;
    for (const LocalVar& v : L.vars) unknowns += !outside(v);
    std::vector<bool> assigned(L.vars.size(), false);
    for (const auto& w : L.whens) {
      for (const auto& a : w.assigns) assigned[a.first] = true;
    }
    for (const auto& im : L.impacts) assigned[im.contact] = true;
    for (size_t k = 0; k < L.vars.size(); ++k) {
      if (assigned[k] && !outside(L.vars[k])) --unknowns;
    }
    size_t equations = L.equations.size() + L.impacts.size();
    size_t flows = 0, inputs = 0, set = 0;
    for (size_t k = 0; k < L.vars.size(); ++k) {
      flows += L.vars[k].sub < 0 && L.vars[k].is_flow;
      inputs += L.vars[k].sub < 0 && L.vars[k].is_input;
      set += assigned[k] && !outside(L.vars[k]);
    }
    if (equations == unknowns) return;
    const ComponentSpec* user = current_component_;
    std::string who = user ? user->name + " (" + type->name + ")" : type->name;
    throw ModelError(user ? user->loc : type->loc,
                     who + " is not balanced: it has " + Counted(equations, "equation") + " for " +
                         Counted(unknowns, "unknown") + " (" + Counted(L.vars.size(), "variable") +
                         ", less " + Counted(flows, "flow variable") + " of its connectors, " +
                         Counted(inputs, "signal input") + " and " + Counted(set, "variable") +
                         " set by when-clauses or impacts" +
                         (L.subs.empty() ? "" : "; its parts' equations and its connections included") + "); " +
                         (equations > unknowns ? "remove the extra equation or add the variable it determines"
                                               : "add an equation for each variable nothing determines") +
                         " (type defined at " + type->loc.ToString() + ")");
  }

  /// The elements of a table's value row by row, with its rows and columns: a list of rows of one
  /// length (`[[0, 1], [1, 2]]`) for a matrix table, a list of numbers for a vector (one column).
  /// The declared fixed sizes must match.
  static std::vector<AstPtr> TableElements(const AstPtr& value, const ParameterDecl& d, const SourceLoc& loc,
                                           const std::string& who, uint32_t* rows, uint32_t* cols) {
    const std::string example = d.shape.size() == 1 ? "[0, 1, 2]" : "[[0, 1], [1, 2]]";
    const std::string expected = "the value of " + who + " (shape " + ShapeText(d.shape) + ") must be a list of " +
                                 (d.shape.size() == 1 ? "numbers" : "rows of one length") + ", e.g. " + example;
    std::vector<AstPtr> elements;
    const bool list = value->kind == Ast::Kind::kArray;
    if (d.shape.size() == 1) {
      if (!list) throw ModelError(loc, expected);
      for (const AstPtr& e : value->args) {
        if (e->kind == Ast::Kind::kArray) throw ModelError(loc, expected + "; found a nested list");
        elements.push_back(e);
      }
      *rows = static_cast<uint32_t>(elements.size());
      *cols = 1;
    } else {
      if (!list || value->args[0]->kind != Ast::Kind::kArray) throw ModelError(loc, expected);
      *rows = static_cast<uint32_t>(value->args.size());
      *cols = static_cast<uint32_t>(value->args[0]->args.size());
      for (size_t r = 0; r < value->args.size(); ++r) {
        const Ast& row = *value->args[r];
        if (row.kind != Ast::Kind::kArray || row.args.size() != *cols) {
          throw ModelError(loc, expected + "; row " + std::to_string(r + 1) + " has " +
                                    std::to_string(row.kind == Ast::Kind::kArray ? row.args.size() : 1) +
                                    " elements, row 1 has " + std::to_string(*cols));
        }
        for (const AstPtr& e : row.args) {
          if (e->kind == Ast::Kind::kArray) throw ModelError(loc, expected + "; found a list nested deeper");
          elements.push_back(e);
        }
      }
    }
    const Shape found = d.shape.size() == 1 ? Shape{static_cast<int>(*rows)}
                                            : Shape{static_cast<int>(*rows), static_cast<int>(*cols)};
    for (size_t k = 0; k < d.shape.size(); ++k) {
      if (d.shape[k] != kOpenSize && d.shape[k] != found[k]) {
        throw ModelError(loc, "the value of " + who + " has shape " + ShapeText(found) + ", but it is declared with shape " +
                                  ShapeText(d.shape));
      }
    }
    if (elements.size() > kMaxArrayElements) {
      throw ModelError(loc, "the value of " + who + " has " + std::to_string(elements.size()) + " elements, more than " +
                                std::to_string(kMaxArrayElements));
    }
    return elements;
  }

  /// The table operand of `interpolate(table, x[, column])`: a table of the type, and a column
  /// that is a whole number (default 2), checked against the declared columns.
  TNode TableOperand(const TypeLayout& L, const Ast& a, const std::string& text, const SourceLoc& loc,
                     size_t dims) {
    const std::string& owner = L.type->name;
    const Ast& name = *a.args[0];
    std::vector<std::string> tables;
    for (const auto& slot : L.tables) tables.push_back(slot.decl->name);
    const std::string valid = " (tables of " + owner + ": " + (tables.empty() ? "none; declare one with shape: [\":\", 2]" : JoinNames(tables)) + ")";
    auto found = name.kind == Ast::Kind::kName && name.path.size() == 1 && !name.path[0].index
                     ? L.table_index.find(name.path[0].name)
                     : L.table_index.end();
    if (found == L.table_index.end()) {
      throw ModelError(loc.Shifted(name.column), "the first argument of interpolate() must name a table, found '" +
                                                     AstToString(name) + "' in '" + text + "' of " + owner + valid);
    }
    const ParameterDecl& d = *L.tables[found->second].decl;
    if (d.shape.size() != dims) {
      throw ModelError(loc.Shifted(name.column),
                       a.op + "() takes " + (dims == 2 ? "a table of rows {x, y1, y2, …}" : "a vector of times") + ", but " +
                           owner + "." + d.name + " has shape " + ShapeText(d.shape) + ", in '" + text + "'");
    }
    double column = dims == 2 ? 2 : 1;
    if (dims == 2 && a.args.size() >= 3) {
      std::optional<double> c = ConstantValue(*a.args[2], template_loop_);
      if (!c && a.args[2]->kind == Ast::Kind::kName) {
        column = 0;  // a parameter: the caller adds it as the node's child c
      } else if (!c || *c != std::floor(*c) || *c < 1 || (d.shape[1] != kOpenSize && *c > d.shape[1])) {
        throw ModelError(loc.Shifted(a.args[2]->column),
                         "the column of " + a.op + "() must be a whole number from 1 to the table's columns" +
                             std::string(d.shape[1] != kOpenSize ? " (" + std::to_string(d.shape[1]) + ")" : "") +
                             ", found '" + AstToString(*a.args[2]) + "' in '" + text + "' of " + owner);
      } else {
        column = *c;
      }
    }
    TNode n;
    n.kind = TNode::kTable;
    n.local = found->second;
    n.value = column;
    return n;
  }

  Template EquationTemplate(const TypeLayout& L, const EquationDecl& e) {
    Template t;
    const std::string quoted = Excerpt(e.text, 0);  // messages quote the text
    int32_t lhs = AddTemplate(L, *e.ast.lhs, quoted, e.loc, false, &t);
    int32_t rhs = AddTemplate(L, *e.ast.rhs, quoted, e.loc, false, &t);
    TNode n;
    n.kind = TNode::kOp;
    n.op = Op::kSub;
    n.a = lhs;
    n.b = rhs;
    t.nodes.push_back(n);
    t.root = static_cast<int32_t>(t.nodes.size() - 1);
    return t;
  }

  Template MakeTemplate(const TypeLayout& L, const Ast& a, const std::string& text,
                        const SourceLoc& loc, bool params_only) {
    Template t;
    t.root = AddTemplate(L, a, Excerpt(text, 0), loc, params_only, &t);
    return t;
  }

  int32_t AddTemplate(const TypeLayout& L, const Ast& a, const std::string& text,
                      const SourceLoc& loc, bool params_only, Template* t) {
    TNode n;
    auto push = [&](TNode node) {
      t->nodes.push_back(node);
      return static_cast<int32_t>(t->nodes.size() - 1);
    };
    auto child = [&](size_t k) { return AddTemplate(L, *a.args[k], text, loc, params_only, t); };
    const std::string& owner = L.type->name;
    switch (a.kind) {
      case Ast::Kind::kNumber:
      case Ast::Kind::kBool:
        n.kind = TNode::kConst;
        n.value = a.number;
        return push(n);
      case Ast::Kind::kName: {
        if (template_loop_ && a.path.size() == 1 && !a.path[0].index && a.path[0].name == template_loop_->first) {
          n.kind = TNode::kConst;  // the element index i in a part array's modifiers
          n.value = template_loop_->second;
          return push(n);
        }
        std::string local = LocalPath(a, loc, text);
        auto v = L.var_index.find(local);
        if (v != L.var_index.end()) {
          if (params_only) {
            throw ModelError(loc.Shifted(a.column), "'" + local + "' is a variable of " + owner +
                                                        "; a parameter's value or a start value may only use parameters, in '" + text + "'");
          }
          n.kind = TNode::kLocalVar;
          n.local = v->second;
          return push(n);
        }
        if (L.table_index.count(local)) {
          throw ModelError(loc.Shifted(a.column), "'" + local + "' is a table of " + owner +
                                                      "; read it with interpolate(" + local + ", x), in '" + text + "'");
        }
        auto p = L.param_index.find(local);
        if (p != L.param_index.end()) {
          n.kind = TNode::kLocalParam;
          n.local = p->second;
          return push(n);
        }
        if (local == "time" && !params_only) {
          n.kind = TNode::kTime;
          return push(n);
        }
        if (local == "pi") {
          n.kind = TNode::kConst;
          n.value = M_PI;
          return push(n);
        }
        auto names = L.LocalNames();
        auto close = ClosestNames(local, names);
        throw ModelError(loc.Shifted(a.column),
                         "unknown name '" + local + "' in '" + text + "' of " + owner +
                             (close.empty() ? "" : " (did you mean " + JoinNames(close) + "?)") +
                             " (valid names: " + JoinNames(names) + ", time, pi)");
      }
      case Ast::Kind::kArray:
        throw ModelError(loc.Shifted(a.column), "an array where a number is expected, in '" + text + "' of " + owner);
      case Ast::Kind::kUnary:
        n.kind = TNode::kOp;
        n.op = a.op == "not" ? Op::kNot : Op::kNeg;
        n.a = child(0);
        return push(n);
      case Ast::Kind::kBinary:
      case Ast::Kind::kSum:
      case Ast::Kind::kProduct: {
        // A chain as a balanced tree, as in BuildExpr.
        std::vector<int32_t> operands;
        for (size_t k = 0; k < a.args.size(); ++k) operands.push_back(child(k));
        return BuildChain(operands, ChainInverse(a), [&](int32_t x, bool inverse, int32_t y) {
          TNode op;
          op.kind = TNode::kOp;
          op.op = ChainOp(a, inverse);
          op.a = x;
          op.b = y;
          return push(op);
        });
      }
      case Ast::Kind::kIf: {
        // An elseif chain nested from the last branch.
        std::vector<int32_t> operands;
        for (size_t k = 0; k < a.args.size(); ++k) operands.push_back(child(k));
        return BuildIfChain(operands, [&](int32_t c, int32_t x, int32_t y) {
          TNode branch;
          branch.kind = TNode::kOp;
          branch.op = Op::kIf;
          branch.a = c;
          branch.b = x;
          branch.c = y;
          return push(branch);
        });
      }
      case Ast::Kind::kCall: {
        Op op;
        if (FunctionOp(a.op, &op)) {
          n.kind = TNode::kOp;
          n.op = op;
          n.a = child(0);
          if (Arity(op) == 2) n.b = child(1);
          return push(n);
        }
        SourceLoc at = loc.Shifted(a.column);
        if (params_only) throw ModelError(at, a.op + "() cannot be used in a parameter's value, in '" + text + "'");
        if (a.op == "noEvent") {
          n.kind = TNode::kNoEvent;
          n.a = child(0);
          return push(n);
        }
        if (a.op == "timeTable" || a.op == "booleanTable") {
          const bool boolean = a.op == "booleanTable";
          TNode table = TableOperand(L, a, text, loc, boolean ? 1 : 2);
          if (table.value == 0) table.c = child(2);
          n.kind = boolean ? TNode::kBooleanTable : TNode::kTimeTable;
          n.a = child(1);
          n.b = push(table);
          if (!boolean) {
            n.c = child(3);
            n.local = static_cast<uint32_t>(child(4));
          }
          return push(n);
        }
        if (a.op == "interpolate") {
          TNode table = TableOperand(L, a, text, loc, 2);
          if (table.value == 0) table.c = child(2);
          n.kind = TNode::kOp;
          n.op = Op::kInterp;
          n.a = child(1);
          n.b = push(table);
          return push(n);
        }
        if (a.op == "der") {
          n.kind = TNode::kDerOf;
          n.a = child(0);
          return push(n);
        }
        if (a.op == "initial") {
          n.kind = TNode::kInitial;
          return push(n);
        }
        if (a.op == "reinit") throw ModelError(at, "reinit() belongs in a when-clause, in '" + text + "'");
        int32_t x = child(0);
        if (t->nodes[x].kind != TNode::kLocalVar) {
          throw ModelError(at, a.op + "() takes a variable, in '" + text + "'");
        }
        TNode pre;
        pre.kind = TNode::kPre;
        pre.local = t->nodes[x].local;
        int32_t pre_id = push(pre);
        if (a.op == "pre") return pre_id;
        TNode r;
        r.kind = TNode::kOp;
        if (a.op == "edge") {
          TNode notp;
          notp.kind = TNode::kOp;
          notp.op = Op::kNot;
          notp.a = pre_id;
          int32_t not_id = push(notp);
          r.op = Op::kAnd;
          r.a = x;
          r.b = not_id;
        } else {  // change
          r.op = Op::kNe;
          r.a = x;
          r.b = pre_id;
        }
        return push(r);
      }
    }
    return -1;
  }

  /// Copies a template into the pool for one instance.
  ExprId Instantiate(const Template& t, VarId first_var, ParamId first_param, InstanceId inst,
                     const std::string& text, const SourceLoc& loc) {
    ExprPool& p = pool();
    // The nodes that read a table need the instance's tables.
    auto table_node = [&](const TNode& n, const std::vector<ExprId>& made) -> ExprId {
      switch (n.kind) {
        case TNode::kTable: {
          const InstanceTable& table = instance_tables_.at(n.local);
          const auto column = static_cast<uint32_t>(n.c >= 0 ? OptionValue(made[n.c], "column", loc) : n.value);
          if (table.cols > kMaxTableColumns) {
            throw ModelError(loc, flat_.InstancePath(inst) + ": interpolate() reads a table with " + std::to_string(table.cols) +
                                      " columns, more than the " + std::to_string(kMaxTableColumns) + " a table may have, in '" +
                                      Excerpt(text, 0) + "'");
          }
          if (column < 1 || column > table.cols) {
            throw ModelError(loc, flat_.InstancePath(inst) + ": interpolate() reads column " + std::to_string(column) + " of a table with " +
                                      std::to_string(table.cols) + " columns, in '" + Excerpt(text, 0) + "'");
          }
          return p.Table(table.first, table.rows, table.cols, column);
        }
        case TNode::kTimeTable:
          return TimeTableExpr(made[n.a], made[n.b], static_cast<int>(OptionValue(made[n.c], "smoothness", loc)),
                               static_cast<int>(OptionValue(made[n.local], "extrapolation", loc)));
        case TNode::kBooleanTable:
          return BooleanTableSum(&p, made[n.a], made[n.b]);
        default:
          MOMENTA_CHECK_MSG(false, "only table nodes are made here");
          return ExprId();
      }
    };
    return CopyTemplate(&p, t, first_var, first_param, &scratch_, table_node);
  }

  // -------------------------------------------------------------------------------------------
  // Tables read with events (core/flatten/time_table.h)

  /// The value of a structural option of timeTable(): a number, or a parameter whose value is a
  /// number (recorded as structural, so -p cannot change it after the build).
  double OptionValue(ExprId e, const std::string& what, const SourceLoc& loc) {
    ExprPool& p = pool();
    double v = 0;
    if (p.IsConst(e)) {
      v = p.ConstValue(e);
    } else if (p.op(e) == Op::kParam) {
      const ParamId id(p.node(e).a);
      const FlatParameter& fp = flat_.parameters[id.value()];
      const std::string name = flat_.ParameterName(id);
      auto ov = overrides_.find(name);
      if (ov != overrides_.end()) {
        v = ov->second;
      } else if (p.IsConst(fp.binding)) {
        v = p.ConstValue(fp.binding);
      } else {
        throw ModelError(fp.loc, name + " sets the " + what + " of a table, which shapes the equations: give it a number");
      }
      structural_[name] = v;
    } else {
      throw ModelError(loc, "the " + what + " of a table must be a number or a parameter");
    }
    if (what == "column") {
      if (v != std::floor(v)) throw ModelError(loc, "the column of a table must be a whole number, found " + NumberText(v));
      return v;
    }
    const bool ok = what == "smoothness" ? (v == kLinearSegments || v == kConstantSegments)
                                         : (v == kHoldLastPoint || v == kLastTwoPoints);
    if (!ok) {
      throw ModelError(loc, "the " + what + " of a table is " + NumberText(v) + "; valid: " +
                                (what == "smoothness" ? "1 (LinearSegments), 3 (ConstantSegments)"
                                                      : "1 (HoldLastPoint), 2 (LastTwoPoints)"));
    }
    return v;
  }

  /// timeTable(): which times repeat (a jump) shapes the sum, so the check of the parameters
  /// keeps them as built.
  ExprId TimeTableExpr(ExprId x, ExprId table, int smoothness, int extrapolation) {
    const Node t = pool().node(table);
    FlatTable& flat_table = FlatTableAt(t.a);
    flat_table.jumps.assign(t.b, 0);
    for (uint32_t r = 0; r + 1 < t.b; ++r) {
      flat_table.jumps[r] = BuildValue(ParamId(t.a + r * t.TableColumns())) == BuildValue(ParamId(t.a + (r + 1) * t.TableColumns()));
    }
    return TimeTableSum(&pool(), x, table, smoothness, extrapolation, flat_table.jumps);
  }

  /// The FlatSystem entry of the current instance's table whose element [1,1] is `first`.
  FlatTable& FlatTableAt(uint32_t first) {
    for (const InstanceTable& it : instance_tables_) {
      if (it.first.value() == first) return flat_.tables[it.flat_index];
    }
    MOMENTA_CHECK_MSG(false, "a table read belongs to its instance");
    return flat_.tables.front();
  }

  /// A parameter's value as the model is built: its -p override or its constant binding (NaN
  /// when it is an expression).
  double BuildValue(ParamId id) {
    const FlatParameter& fp = flat_.parameters[id.value()];
    auto ov = overrides_.find(flat_.ParameterName(id));
    if (ov != overrides_.end()) return ov->second;
    return pool().IsConst(fp.binding) ? pool().ConstValue(fp.binding) : std::nan("");
  }

  // -------------------------------------------------------------------------------------------
  // Model variables and components

  void ModelVariables() {
    for (const auto& v : spec_.variables) {
      if (model_param_.count(v.name) || model_var_.count(v.name)) {
        throw ModelError(v.loc, v.name + " is declared twice");
      }
      FlatVariable fv;
      fv.name = flat_.Own(v.name);
      fv.type = v.type;
      fv.fixed = v.fixed;
      fv.nominal = v.nominal;
      fv.state_priority = v.state_priority;
      fv.loc = v.loc;
      flat_.model_variable_units.push_back(flat_.Own(v.unit));
      fv.start = v.start ? StartExpr(*v.start, v.loc, nullptr) : ExprId();
      fv.discrete = v.type != ValueType::kReal;
      model_var_[v.name] = VarId(flat_.variables.size());
      flat_.variables.push_back(fv);
    }
  }

  void Components() {
    ReserveComponents();
    for (size_t s = 0; s < spec_.components.size(); ++s) {
      const ComponentSpec& c = spec_.components[s];
      if (arrays_.Find(c.name) || model_param_.count(c.name) || model_var_.count(c.name)) {
        throw ModelError(c.loc, "the name " + c.name + " is used twice");
      }
      const ComponentType* type = FindType(c.type);
      if (!type) UnknownType(c);
      current_component_ = &c;
      const TypeLayout& L = Layout(type);
      ComponentArray arr{s, static_cast<uint32_t>(flat_.instances.size()), 1, c.count != nullptr,
                         static_cast<uint32_t>(1 + L.subs.size())};
      if (c.count) arr.count = ArrayCount(c, L);
      planned_bytes_ += EstimatedBytes(L);
      if (arr.is_array) ReserveElements(L, arr.count);
      // Which modifiers set parameters and which set start values.
      std::vector<const Modifier*> param_mod(L.params.size(), nullptr);
      std::vector<const Modifier*> var_mod(L.vars.size(), nullptr);
      table_mod_.assign(L.tables.size(), nullptr);
      for (const auto& m : c.modifiers) {
        if (auto t = L.table_index.find(m.key); t != L.table_index.end()) {
          if (!m.value) throw ModelError(m.loc, c.name + "." + m.key + " is a table: give its value, e.g. " + m.key + ": [[0, 1], [1, 2]]");
          table_mod_[t->second] = &m;
          continue;
        }
        auto [is_param, k] = ModifierTarget(c, L, m);
        (is_param ? param_mod : var_mod)[k] = &m;
      }
      const int32_t block = arr.is_array ? BeginBlock(c, L) : -1;
      const int32_t names = NamesOf(L);
      for (uint32_t k = 0; k < arr.count; ++k) {
        std::pair<std::string, double> index{"i", static_cast<double>(k + 1)};
        AddInstance(c, L, block, names, param_mod, var_mod, arr.is_array ? &index : nullptr);
      }
      if (block >= 0) EndBlock(&flat_.blocks[block]);
      arrays_.Add(c.name, arr);
    }
  }

  /// Room for the components written one by one (a count: array reserves its own, from its
  /// count): the flat system's records, the expression pool's table and the names of the
  /// components take their memory once, at their size, instead of doubling as 100 000
  /// components fill them (which copies the records and leaves up to half of them unused). A
  /// type that cannot be laid out is left to the loop in Components, which reports it in the
  /// model's order; nothing is reserved then. Composite types are not counted.
  void ReserveComponents() {
    arrays_.Reserve(spec_.components.size());
    struct Use {
      const ComponentSpec* first;
      size_t count;
    };
    std::unordered_map<std::string_view, size_t> use_of;  // type name -> uses[]
    std::vector<Use> uses;
    for (const ComponentSpec& c : spec_.components) {
      if (c.count) continue;
      auto [at, added] = use_of.emplace(c.type, uses.size());
      if (added) uses.push_back({&c, 0});
      ++uses[at->second].count;
    }
    size_t instances = 0, slots = 0, vars = 0, params = 0, equations = 0, initials = 0, nodes = 0;
    for (const Use& u : uses) {
      const ComponentType* type = FindType(u.first->type);
      // A composite's layout is checked against the memory budget with the components before
      // it: it is laid out in the loop, in its place.
      if (!type || !type->components.empty()) continue;
      const TypeLayout* L = nullptr;
      current_component_ = u.first;
      try {
        L = &Layout(type);
      } catch (const ModelError&) {
        laying_out_.clear();
        template_loop_ = nullptr;
        current_component_ = nullptr;
        return;
      }
      current_component_ = nullptr;
      instances += u.count * (1 + L->subs.size());
      slots += u.count * L->connectors.size();
      vars += u.count * L->vars.size();
      params += u.count * L->params.size();
      equations += u.count * (L->equations.size() + L->impacts.size() + Joins(*L));
      initials += u.count * L->initial_equations.size();
      nodes += u.count * (InstanceNodes(*L) + Joins(*L));
    }
    equations += spec_.equations.size();
    initials += spec_.initial_equations.size();
    auto room = [](auto* records, size_t more) { records->reserve(records->size() + more); };
    room(&flat_.instances, instances);
    room(&instance_data_, instances);
    room(&slot_instance_, slots);
    room(&flat_.variables, vars);
    room(&flat_.parameters, params);
    room(&flat_.equations, equations);
    room(&flat_.initial_equations, initials);
    // The build reserves twice the flattened pool for the passes after flattening (core/build.cc):
    // the table is made at that size at once, not grown through the sizes on the way.
    pool().Reserve(2 * (pool().size() + nodes));
  }

  /// About how many connection equations an instance of L adds: a connection set of s physical
  /// connectors makes s times their potentials' count of equations (s - 1 equal potentials and
  /// one flow sum each, as many flows as potentials); a signal set fewer than its connectors.
  static size_t Joins(const TypeLayout& L) {
    size_t joins = 0;
    for (const ConnectorSlot& c : L.connectors) joins += c.type->is_signal ? 1 : c.type->potentials.size();
    return joins;
  }

  /// About how many new nodes of the expression pool an instance of L makes: its templates'
  /// operations and distinct leaves (constants and time are shared by all instances).
  static size_t InstanceNodes(const TypeLayout& L) {
    std::unordered_set<uint64_t> leaves;
    size_t ops = 0;
    for (const auto* list : {&L.equations, &L.initial_equations, &L.param_defaults, &L.starts}) {
      for (const Template& t : *list) {
        for (const TNode& n : t.nodes) {
          if (n.kind == TNode::kLocalVar || n.kind == TNode::kLocalParam || n.kind == TNode::kPre) {
            leaves.insert(uint64_t{n.kind} << 32 | n.local);
          } else if (n.kind != TNode::kConst && n.kind != TNode::kTime && n.kind != TNode::kInitial) {
            ++ops;
          }
        }
      }
    }
    return ops + leaves.size();
  }

  /// The record of a count: array (FlatSystem::blocks), begun before its first element is made;
  /// its strides are set by EndBlock.
  int32_t BeginBlock(const ComponentSpec& c, const TypeLayout& L) {
    FlatBlock b;
    b.name = c.name;
    b.type = L.type;
    b.loc = c.loc;
    b.first_instance = InstanceId(flat_.instances.size());
    b.first_var = VarId(flat_.variables.size());
    b.first_param = ParamId(flat_.parameters.size());
    b.first_equation = static_cast<uint32_t>(flat_.equations.size());
    b.first_initial = static_cast<uint32_t>(flat_.initial_equations.size());
    b.stride = static_cast<uint32_t>(1 + L.subs.size());
    for (const SubInstance& sub : L.subs) b.part_paths.push_back(sub.path);
    flat_.blocks.push_back(std::move(b));
    return static_cast<int32_t>(flat_.blocks.size() - 1);
  }

  /// A block's count and strides, from what its elements added (every element adds as many).
  void EndBlock(FlatBlock* b) {
    b->count = (static_cast<uint32_t>(flat_.instances.size()) - b->first_instance.value()) / b->stride;
    b->vars_per = (static_cast<uint32_t>(flat_.variables.size()) - b->first_var.value()) / b->count;
    b->params_per = (static_cast<uint32_t>(flat_.parameters.size()) - b->first_param.value()) / b->count;
    b->equations_per = (static_cast<uint32_t>(flat_.equations.size()) - b->first_equation) / b->count;
    b->initials_per = (static_cast<uint32_t>(flat_.initial_equations.size()) - b->first_initial) / b->count;
  }

  /// Holds a text in the flat system (FlatSystem::texts) and returns its index.
  uint32_t HeldText(std::string text) {
    flat_.texts.push_back(std::move(text));
    return static_cast<uint32_t>(flat_.texts.size() - 1);
  }

  /// Room in the flat system's arrays for `count` instances of L, made before they are added: a
  /// large array then takes its memory once, at its size, instead of doubling (which copies the
  /// records at every step and leaves up to half of the last block unused). It still grows
  /// geometrically over many small arrays.
  void ReserveElements(const TypeLayout& L, uint32_t count) {
    auto room = [count](auto* records, size_t per_element) {
      const size_t needed = records->size() + size_t{count} * per_element;
      if (needed > records->capacity()) records->reserve(std::max(needed, records->capacity() + records->capacity() / 2));
    };
    room(&flat_.instances, 1 + L.subs.size());
    room(&instance_data_, 1 + L.subs.size());
    room(&slot_instance_, L.connectors.size());
    room(&flat_.variables, L.vars.size());
    room(&flat_.parameters, L.params.size());  // tables' elements come on top
    room(&flat_.equations, L.equations.size() + L.impacts.size());
    room(&flat_.initial_equations, L.initial_equations.size());
    // The pool's table at the size the build reserves after flattening (twice the flattened
    // pool, core/build.cc), so that it is made once per array instead of grown through the sizes
    // on the way (the RC ladder: a rehash every half again).
    pool().Reserve(2 * (pool().size() + size_t{count} * (InstanceNodes(L) + Joins(L))));
  }

  [[noreturn]] void UnknownType(const ComponentSpec& c) const {
    std::vector<std::string> names = library_.ComponentNames();
    for (const auto& d : spec_.defines) names.push_back(d.name);
    auto close = ClosestNames(c.type, names);
    throw ModelError(c.type_loc, "unknown component type '" + c.type + "' for " + c.name +
                                     (close.empty() ? "" : " (did you mean " + JoinNames(close) + "?)") +
                                     " (valid types: " + JoinNames(names, 80) + ")");
  }

  /// Estimated bytes of one instance of a type through the build (core/base/memory_budget.h).
  static double EstimatedBytes(const TypeLayout& L) {
    size_t nodes = 0;
    for (const auto* list : {&L.equations, &L.initial_equations, &L.param_defaults, &L.starts}) {
      for (const Template& t : *list) nodes += t.nodes.size();
    }
    // A composite's names carry its parts' paths: their text, in the layout and in every
    // instance's flat names, counts too.
    double names = 0;
    if (!L.subs.empty()) {
      for (const auto& v : L.vars) names += static_cast<double>(v.name.size());
      for (const auto& p : L.params) names += static_cast<double>(p.name.size());
      for (const auto& sub : L.subs) names += static_cast<double>(sub.path.size());
    }
    return EstimatedComponentBytes(L.vars.size(), L.params.size(), nodes) + 4 * names;
  }

  /// The value of `count:`: a whole number of at least 1 whose components fit, with the rest of
  /// the model, in the memory budget (and in momenta's 32-bit indices) — checked before any of
  /// them is made, so an impossible count is refused at once.
  uint32_t ArrayCount(const ComponentSpec& c, const TypeLayout& L) {
    std::string text = AstToString(*c.count);
    std::string what = "count of " + c.name;
    double n = StructuralWhole(*c.count, text, c.loc, nullptr, what);
    return CheckedCount(c, L, n, what, text);
  }

  /// `n` elements of type layout L, checked: a whole number of at least 1 whose components fit,
  /// with the rest of the model, in the memory budget and in momenta's 32-bit indices.
  uint32_t CheckedCount(const ComponentSpec& c, const TypeLayout& L, double n, std::string what,
                        const std::string& text) {
    std::string value = NumberText(n);
    if (!std::isfinite(n) || n != std::floor(n)) throw ModelError(c.loc, what + " must be a whole number, found " + value);
    if (value != text) what += " ('" + text + "')";
    if (n < 1) throw ModelError(c.loc, what + " must be at least 1, found " + value);
    double bytes = planned_bytes_ + n * EstimatedBytes(L);
    if (!budget_) budget_ = BuildMemoryBudget();
    if (bytes > budget_->bytes) {
      throw ModelError(c.loc, what + " is " + value + ": " + value + " " + L.type->name + " components (" +
                                  Counted(L.vars.size(), "variable") + ", " +
                                  Counted(L.params.size(), "parameter") + " each) need about " +
                                  ByteText(bytes) + " of memory to build, more than the budget of " +
                                  ByteText(budget_->bytes) + " (" + budget_->source + ")");
    }
    NotePlannedBuild(bytes);
    // Instances, variables and parameters are numbered with 32-bit indices.
    double ids = std::max({static_cast<double>(flat_.instances.size()), static_cast<double>(flat_.variables.size()),
                           static_cast<double>(flat_.parameters.size())}) +
                 n * static_cast<double>(std::max({L.vars.size(), L.params.size(), L.subs.size() + 1}));
    if (ids >= 2147483648.0) {
      throw ModelError(c.loc, what + " is " + value + ": more components, variables or parameters than " +
                                  "momenta numbers (2^31)");
    }
    return static_cast<uint32_t>(n);
  }

  /// The nodes below the root of an equation that is not made, in their order: one may be
  /// shared with another equation, and the pool orders the operands of a commutative operation
  /// by node id, so every node that is made keeps the place it has when all equations are made
  /// (and the build makes the same programs). The root is the template's last node; a root that
  /// is a leaf (f = 0) is made too, as Connections makes an unconnected flow's.
  void MakeBelowRoot(const Template& t, VarId first_var, ParamId first_param) {
    MOMENTA_CHECK_MSG(static_cast<size_t>(t.root) + 1 == t.nodes.size(), "a template's root is its last node");
    const bool leaf_root = t.nodes.back().kind != TNode::kOp;
    CopyTemplate(&pool(), t, first_var, first_param, &scratch_, NoTable, /*cached_constants=*/true,
                 leaf_root ? t.nodes.size() : t.nodes.size() - 1);
  }

  /// For each equation of L, the DeferredAliases shape of its copies, or kNotSure when they are
  /// made; read once per layout. A local variable of a conditional connector (L's or a part's)
  /// makes its equations made: they may go when the connector is absent
  /// (ResolveConditionalConnectors).
  const std::vector<uint32_t>& SureAliasShapes(const TypeLayout& L) {
    auto [at, added] = sure_shapes_.emplace(&L, std::vector<uint32_t>());
    if (!added) return at->second;
    std::vector<bool> conditional(L.vars.size(), false);
    auto mark = [&](const TypeLayout& T, uint32_t var_off) {
      for (const ConnectorSlot& cs : T.connectors) {
        if (cs.decl->condition.empty()) continue;
        const size_t count = cs.type->is_signal ? 1 : cs.type->potentials.size() + cs.type->flows.size();
        for (size_t j = 0; j < count; ++j) conditional[var_off + cs.first_local_var + j] = true;
      }
    };
    mark(L, 0);
    for (const SubInstance& sub : L.subs) mark(*sub.layout, sub.first_var);
    std::vector<uint32_t>& shapes = at->second;
    for (const Template& t : L.equations) {
      const SureAlias form = ReadSureAlias(t, L.discrete, conditional);
      shapes.push_back(form.sure ? deferred_->AddShape(t, form) : kNotSure);
    }
    return shapes;
  }

  /// The names of L's variables, parameters, equations and when-clauses (FlatSystem::type_names),
  /// made once: every instance's are made from them on demand.
  int32_t NamesOf(const TypeLayout& L) {
    auto [at, added] = names_of_.emplace(&L, static_cast<int32_t>(flat_.type_names.size()));
    if (!added) return at->second;
    auto n = std::make_shared<TypeNames>();
    for (const LocalVar& v : L.vars) {
      n->vars.push_back(v.name);
      n->var_units.push_back(v.unit);
    }
    for (const LocalParam& p : L.params) {
      n->params.push_back(p.name);
      n->param_units.push_back(p.decl->unit);
      n->param_docs.push_back(p.decl->doc);
    }
    for (const auto* infos : {&L.equation_info, &L.initial_info}) {  // the equations, then the initial ones
      for (const PartInfo& info : *infos) n->equations.push_back(info.text);
    }
    for (const PartInfo& info : L.when_info) n->whens.push_back(info.text);
    flat_.type_names.push_back(std::move(n));
    return at->second;
  }

  /// Makes one instance of L: an element of `block` (the `index`-th), or the component alone
  /// (block -1); `names` are L's (NamesOf).
  void AddInstance(const ComponentSpec& c, const TypeLayout& L, int32_t block, int32_t names,
                   const std::vector<const Modifier*>& param_mod,
                   const std::vector<const Modifier*>& var_mod,
                   const std::pair<std::string, double>* index) {
    const ComponentType* type = L.type;
    InstanceId inst(flat_.instances.size());
    // An element of a block is named by the block; a component alone holds its path.
    auto instance = [&](const ComponentType* t, const SourceLoc& loc, int32_t type_names, const std::string* part) {
      FlatInstance fi;
      fi.type = t;
      fi.loc = loc;
      fi.names = type_names;
      fi.block = block;
      if (block < 0) fi.path_text = HeldText(part ? c.name + "." + *part : c.name);
      flat_.instances.push_back(fi);
    };
    instance(type, c.loc, names, nullptr);
    InstanceData data{&L, VarId(flat_.variables.size()), ParamId(flat_.parameters.size()),
                      static_cast<uint32_t>(slot_instance_.size())};
    instance_data_.push_back(data);
    for (size_t k = 0; k < L.connectors.size(); ++k) slot_instance_.push_back(inst.value());
    // A composite's parts, at every depth, are instances of their own (for messages).
    for (const SubInstance& sub : L.subs) {
      instance(sub.layout->type, sub.loc, -1, &sub.path);
      instance_data_.push_back({sub.layout, VarId(data.first_var.value() + sub.first_var),
                                ParamId(data.first_param.value() + sub.first_param), kNoSlot});
    }
    auto instance_of = [&](int32_t sub) { return sub < 0 ? inst : InstanceId(inst.value() + 1 + sub); };
    auto loc_of = [&](int32_t sub) { return sub < 0 ? c.loc : L.subs[sub].loc; };
    // Conditional connectors: the instance's own (its connections come later) and its parts'.
    auto conditional = [&](const TypeLayout& S, int32_t sub, uint32_t var_off, uint32_t param_off) {
      for (uint32_t k = 0; k < S.connectors.size(); ++k) {
        const ConnectorSlot& cs = S.connectors[k];
        if (cs.decl->condition.empty()) continue;
        FlatConditionalConnector cc;
        cc.instance = instance_of(sub);
        cc.name = cs.decl->name;
        cc.condition = ParamId(data.first_param.value() + param_off + S.param_index.at(cs.decl->condition));
        cc.first_var = VarId(data.first_var.value() + var_off + cs.first_local_var);
        // A signal connector's one variable counts as a potential: absent, it is set to zero.
        cc.num_potentials = cs.type->is_signal ? 1 : static_cast<uint32_t>(cs.type->potentials.size());
        cc.num_flows = cs.type->is_signal ? 0 : static_cast<uint32_t>(cs.type->flows.size());
        if (sub >= 0) {
          auto at = L.connected.find(var_off + cs.first_local_var);
          if (at != L.connected.end()) cc.connected_at = at->second;
        } else {
          conditional_slot_[data.first_slot + k] = flat_.conditional_connectors.size();
        }
        flat_.conditional_connectors.push_back(std::move(cc));
      }
    };
    conditional(L, -1, 0, 0);
    for (size_t k = 0; k < L.subs.size(); ++k) {
      conditional(*L.subs[k].layout, static_cast<int32_t>(k), L.subs[k].first_var, L.subs[k].first_param);
    }
    // Parameters.
    for (size_t k = 0; k < L.params.size(); ++k) {
      const LocalParam& lp = L.params[k];
      const ParameterDecl& d = *lp.decl;
      FlatParameter fp;
      const TextRef local{TextRef::kType, inst.value(), static_cast<uint32_t>(k)};
      fp.name = local;
      fp.type = d.type;
      if (d.min) fp.min = *d.min;
      if (d.max) fp.max = *d.max;
      if (!d.unit.empty()) fp.unit = local;
      if (!d.doc.empty()) fp.doc = local;
      fp.instance = instance_of(lp.sub);
      if (const Modifier* m = param_mod[k]) {
        const AstPtr value = m->value_unit.empty() ? m->value : ModifierValue(*m, d, flat_.InstancePath(inst));
        fp.binding = ModelExpr(*value, m->value_text, m->loc, index, false);
        fp.loc = m->loc;
      } else {
        fp.binding = Instantiate(L.param_defaults[k], data.first_var, data.first_param, inst, d.value_text, d.loc);
        fp.loc = lp.loc.known() ? lp.loc : loc_of(lp.sub);
      }
      flat_.parameters.push_back(std::move(fp));
    }
    AddTables(c, L, data, inst, index);
    // Variables.
    for (size_t k = 0; k < L.vars.size(); ++k) {
      const LocalVar& lv = L.vars[k];
      FlatVariable fv;
      fv.name = {TextRef::kType, inst.value(), static_cast<uint32_t>(k)};
      fv.type = lv.type;
      fv.is_flow = lv.is_flow;
      fv.is_input = lv.is_input;
      fv.instance = instance_of(lv.sub);
      fv.loc = lv.loc.known() ? lv.loc : loc_of(lv.sub);
      if (lv.decl) {
        fv.fixed = lv.decl->fixed;
        fv.nominal = lv.decl->nominal;
        fv.state_priority = lv.decl->state_priority;
      }
      if (lv.fixed) fv.fixed = *lv.fixed;
      if (lv.state_priority) fv.state_priority = *lv.state_priority;
      if (L.starts[k].root >= 0) {
        fv.start = Instantiate(L.starts[k], data.first_var, data.first_param, inst, "", fv.loc);
      }
      fv.discrete = L.discrete[k];
      if (const Modifier* m = var_mod[k]) {
        if (m->start) fv.start = StartExpr(*m->start, m->loc, index);
        if (m->fixed) fv.fixed = *m->fixed;
        if (m->state_priority) fv.state_priority = *m->state_priority;
        fv.loc = m->loc;
      }
      flat_.variables.push_back(std::move(fv));
    }
    // Equations.
    // Equations that alias elimination surely removes are not made (DeferredAliases).
    const std::vector<uint32_t>* sure_shapes = deferred_ ? &SureAliasShapes(L) : nullptr;
    auto add_equations = [&](const std::vector<Template>& templates, const std::vector<PartInfo>& info,
                             uint32_t first_text, const std::vector<uint32_t>* shapes, std::vector<FlatEquation>* out) {
      for (size_t k = 0; k < templates.size(); ++k) {
        const PartInfo& d = info[k];
        FlatEquation eq;
        if (shapes != nullptr && (*shapes)[k] != kNotSure) {
          MakeBelowRoot(templates[k], data.first_var, data.first_param);
          deferred_->AddCopy(out->size(), (*shapes)[k], data.first_var, data.first_param);
        } else {
          eq.residual = Instantiate(templates[k], data.first_var, data.first_param, inst, d.text, c.loc);
        }
        eq.origin = d.origin;
        eq.instance = d.origin == EquationOrigin::kConnection ? InstanceId() : instance_of(d.sub);
        eq.text = {TextRef::kType, inst.value(), first_text + static_cast<uint32_t>(k)};
        eq.loc = d.loc;
        out->push_back(std::move(eq));
      }
    };
    add_equations(L.equations, L.equation_info, 0, sure_shapes, &flat_.equations);
    // When-clauses and impacts.
    auto inst_expr = [&](const Template& t, const std::string& text) {
      return Instantiate(t, data.first_var, data.first_param, inst, text, c.loc);
    };
    auto var_of = [&](uint32_t local) { return VarId(data.first_var.value() + local); };
    for (size_t k = 0; k < L.whens.size(); ++k) {
      const auto& wt = L.whens[k];
      const PartInfo& info = L.when_info[k];
      FlatWhen w;
      w.condition = inst_expr(wt.condition, info.text);
      for (const auto& [target, value] : wt.assigns) w.assigns.emplace_back(var_of(target), inst_expr(value, ""));
      for (const auto& [target, value] : wt.reinits) w.reinits.emplace_back(var_of(target), inst_expr(value, ""));
      w.instance = instance_of(info.sub);
      w.text = {TextRef::kType, inst.value(), static_cast<uint32_t>(k)};
      w.loc = info.loc;
      flat_.whens.push_back(std::move(w));
    }
    for (const auto& it : L.impacts) {
      const ImpactDecl& d = *it.decl;
      FlatImpact im;
      im.gap = inst_expr(it.gap, d.gap_text);
      im.velocity = inst_expr(it.velocity, d.velocity_text);
      im.restitution = inst_expr(it.restitution, d.restitution_text);
      im.v_small = inst_expr(it.v_small, d.v_small_text);
      im.release = inst_expr(it.release, d.release_text);
      im.force = var_of(it.force);
      im.contact = var_of(it.contact);
      im.instance = instance_of(it.sub);
      im.loc = d.loc;
      // The contact law: no force while open, no relative acceleration while closed.
      ExprPool& p = pool();
      if (p.mask(im.velocity) & kHasDer) {
        throw ModelError(d.loc, "the impact velocity of " + flat_.instances[im.instance.value()].type->name +
                                    " may not contain der()");
      }
      ExprId dvel = TimeDerivative(&p, im.velocity);
      FlatEquation eq;
      eq.residual = p.If(p.Var(im.contact), dvel, p.Var(im.force));
      eq.origin = EquationOrigin::kComponent;
      eq.instance = im.instance;
      eq.text = flat_.Own("0 = if " + d.contact + " then der(" + d.velocity_text + ") else " + d.force + " (impact)");
      eq.loc = d.loc;
      im.mode_equation = static_cast<uint32_t>(flat_.equations.size());
      flat_.equations.push_back(std::move(eq));
      flat_.impacts.push_back(std::move(im));
    }
    add_equations(L.initial_equations, L.initial_info, static_cast<uint32_t>(L.equations.size()), nullptr,
                  &flat_.initial_equations);
  }

  /// An instance's tables: each element a parameter `path.table[i,j]`, row by row, from the
  /// component's value for it or the type's default; recorded for the check of the abscissas.
  void AddTables(const ComponentSpec& c, const TypeLayout& L, const InstanceData& data, InstanceId inst,
                 const std::pair<std::string, double>* index) {
    instance_tables_.clear();
    if (L.tables.empty()) return;
    const std::string path = flat_.InstancePath(inst);
    for (size_t k = 0; k < L.tables.size(); ++k) {
      const TypeLayout::TableSlot& slot = L.tables[k];
      const ParameterDecl& d = *slot.decl;
      const Modifier* m = k < table_mod_.size() ? table_mod_[k] : nullptr;
      InstanceTable table{ParamId(flat_.parameters.size()), slot.rows, slot.cols, flat_.tables.size()};
      std::vector<AstPtr> given;
      if (m) given = TableElements(m->value, d, m->loc, path + "." + d.name, &table.rows, &table.cols);
      const Shape shape = d.shape.size() == 1 ? Shape{static_cast<int>(table.rows)}
                                              : Shape{static_cast<int>(table.rows), static_cast<int>(table.cols)};
      const TextRef unit = flat_.Own(d.unit), doc = flat_.Own(d.doc);  // one for all elements
      for (size_t e = 0; e < static_cast<size_t>(table.rows) * table.cols; ++e) {
        FlatParameter fp;
        fp.name = flat_.Own(path + "." + ElementName(d.name, shape, e));
        fp.unit = unit;
        fp.doc = doc;
        if (d.min) fp.min = *d.min;  // every element: a table of friction forces has min: 0
        if (d.max) fp.max = *d.max;
        fp.instance = inst;
        if (m) {
          fp.binding = ModelExpr(*given[e], m->value_text, m->loc, index, false);
          fp.loc = m->loc;
        } else {
          fp.binding = Instantiate(slot.defaults[e], data.first_var, data.first_param, inst, d.value_text, d.loc);
          fp.loc = c.loc;
        }
        flat_.parameters.push_back(std::move(fp));
      }
      flat_.tables.push_back({path + "." + d.name, table.first, table.rows, table.cols, inst, m ? m->loc : c.loc, {}});
      instance_tables_.push_back(table);
    }
  }

  // -------------------------------------------------------------------------------------------
  // Connections

  /// One end of a connection: an instance's connector, and where the end is written.
  struct EndRef {
    uint32_t instance;
    uint32_t connector;
    SourceLoc loc;
  };

  /// "R[3].n": a connection end as messages name it (made only for a message).
  std::string EndText(const EndRef& e) const {
    return flat_.InstancePath(InstanceId(e.instance)) + "." +
           instance_data_[e.instance].layout->connectors[e.connector].decl->name;
  }

  EndRef ResolveEnd(const Ast& a, const std::string& text, const SourceLoc& loc,
                    const std::pair<std::string, double>* loop) {
    if (a.path.size() > 2 && arrays_.Find(a.path[0].name)) {
      throw ModelError(loc, "'" + text + "' reaches into " + a.path[0].name + "; a model connects to a component's " +
                                "own connectors only (a composite type exposes a part's connector by connecting it " +
                                "to one of its own)");
    }
    if (a.path.size() != 2) {
      throw ModelError(loc, "a connection end names a component and one of its connectors, e.g. A.flange_a; found '" + text + "'");
    }
    const ComponentArray* arr = arrays_.Find(a.path[0].name);
    if (!arr) {
      std::vector<std::string> names;
      for (const auto& c : spec_.components) names.push_back(c.name);
      auto close = ClosestNames(a.path[0].name, names);
      throw ModelError(loc, "unknown component '" + a.path[0].name + "' in connection end '" + text + "'" +
                                (close.empty() ? "" : " (did you mean " + JoinNames(close) + "?)") +
                                " (valid components: " + JoinNames(names) + ")");
    }
    uint32_t inst = ElementOf(*arr, a.path[0], loc, loop, text);
    const TypeLayout& L = *instance_data_[inst].layout;
    if (a.path[1].index) throw ModelError(loc, "connectors cannot be indexed, in '" + text + "'");
    auto c = L.connector_index.find(a.path[1].name);
    if (c == L.connector_index.end()) {
      std::vector<std::string> names;
      for (const auto& s : L.connectors) names.push_back(s.decl->name);
      throw ModelError(loc, flat_.InstancePath(InstanceId(inst)) + " (" + L.type->name + ") has no connector '" +
                                a.path[1].name + "' (valid connectors: " +
                                (names.empty() ? std::string("none") : JoinNames(names)) + ")");
    }
    return {inst, c->second, loc};
  }

  /// The end `component.connector` of a connection held as text (ConnectionSpec::a null: a
  /// plain name) when it names a component that is not an array and one of its connectors;
  /// nothing otherwise, and ResolveEnd reads the end's tree and says what is wrong. (Without a
  /// tree per end: 200 000 ends on a written-out model.)
  std::optional<EndRef> PlainEnd(const AstPtr& tree, const std::string& text, const SourceLoc& loc) const {
    const size_t dot = text.find('.');
    if (tree || dot == std::string::npos || text.find('.', dot + 1) != std::string::npos) return std::nullopt;
    const ComponentArray* arr = arrays_.Find(std::string_view(text).substr(0, dot));
    if (!arr || arr->is_array) return std::nullopt;
    const TypeLayout& L = *instance_data_[arr->first_instance].layout;
    auto connector = L.connector_index.find(text.substr(dot + 1));
    if (connector == L.connector_index.end()) return std::nullopt;
    return EndRef{arr->first_instance, connector->second, loc};
  }

  uint32_t Find(uint32_t x) {
    while (parent_[x] != x) {
      parent_[x] = parent_[parent_[x]];
      x = parent_[x];
    }
    return x;
  }

  /// The number of connections `for: i in a:b` makes, b - a + 1 (none if b < a), and a. Both
  /// bounds are whole numbers, and a range makes at most as many connections as the model has
  /// connectors (a longer one could only repeat them), so 1:1e9 is refused at once.
  size_t LoopLength(const ConnectionSpec& c, double* from) {
    const SourceLoc& loc = c.loop_loc.known() ? c.loop_loc : c.loc;
    std::string range = "the range of 'for: " +
                        (c.loop_text.empty() ? c.loop_var + " in " + AstToString(*c.loop_from) + ":" +
                                                   AstToString(*c.loop_to)
                                             : c.loop_text) +
                        "'";
    *from = StructuralWhole(*c.loop_from, AstToString(*c.loop_from), loc, nullptr, "the start of " + range);
    double to = StructuralWhole(*c.loop_to, AstToString(*c.loop_to), loc, nullptr, "the end of " + range);
    double n = to - *from + 1;
    if (n <= 0) return 0;
    const size_t connectors = slot_instance_.size();
    if (n > static_cast<double>(connectors)) {
      throw ModelError(loc, range + " makes " + NumberText(n) + " connections, more than the model's " +
                                std::to_string(connectors) + " connectors can need; a range runs over " +
                                "the elements of an array, e.g. i in 1:n");
    }
    return static_cast<size_t>(n);
  }

  void Connections() {
    parent_.resize(slot_instance_.size());
    for (uint32_t k = 0; k < parent_.size(); ++k) parent_[k] = k;
    std::vector<SourceLoc> slot_loc(slot_instance_.size());
    auto join = [&](const EndRef& x, const EndRef& y) {
      const ConnectorSlot& cx = instance_data_[x.instance].layout->connectors[x.connector];
      const ConnectorSlot& cy = instance_data_[y.instance].layout->connectors[y.connector];
      if (!Compatible(cx.type, cy.type)) CheckCompatible(cx.type, EndText(x), cy.type, EndText(y), x.loc);
      uint32_t sx = instance_data_[x.instance].first_slot + x.connector;
      uint32_t sy = instance_data_[y.instance].first_slot + y.connector;
      if (sx == sy) throw ModelError(x.loc, "connection of " + EndText(x) + " to itself");
      for (auto [s, e] : {std::pair{sx, &x}, std::pair{sy, &y}}) {
        if (!slot_loc[s].known()) {
          slot_loc[s] = e->loc;
          auto cc = conditional_slot_.find(s);
          if (cc != conditional_slot_.end()) flat_.conditional_connectors[cc->second].connected_at = e->loc;
        }
      }
      parent_[Find(sx)] = Find(sy);
    };
    for (const auto& c : spec_.connections) {
      if (c.loop_var.empty()) {
        const std::optional<EndRef> a = PlainEnd(c.a, c.a_text, c.a_loc), b = PlainEnd(c.b, c.b_text, c.b_loc);
        join(a ? *a : ResolveEnd(*c.EndA(), c.a_text, c.a_loc, nullptr),
             b ? *b : ResolveEnd(*c.EndB(), c.b_text, c.b_loc, nullptr));
        continue;
      }
      double from = 0;
      size_t iterations = LoopLength(c, &from);
      for (size_t k = 0; k < iterations; ++k) {
        std::pair<std::string, double> loop{c.loop_var, from + static_cast<double>(k)};
        join(ResolveEnd(*c.EndA(), c.a_text, c.a_loc, &loop), ResolveEnd(*c.EndB(), c.b_text, c.b_loc, &loop));
      }
    }
    // Group slots into connection sets.
    const std::vector<std::vector<uint32_t>> sets = Classes(parent_.size(), [&](uint32_t x) { return Find(x); });
    flat_.equations.reserve(flat_.equations.size() + ConnectionEquationCount(sets));
    ExprPool& p = pool();
    for (const auto& set : sets) {
      const uint32_t s0 = set[0];
      const InstanceData& d0 = instance_data_[slot_instance_[s0]];
      const ConnectorSlot& c0 = d0.layout->connectors[s0 - d0.first_slot];
      auto var_of = [&](uint32_t slot, uint32_t k) {
        const InstanceData& d = instance_data_[slot_instance_[slot]];
        const ConnectorSlot& cs = d.layout->connectors[slot - d.first_slot];
        return VarId(d.first_var.value() + cs.first_local_var + k);
      };
      auto name_of = [&](uint32_t slot) {
        const InstanceData& d = instance_data_[slot_instance_[slot]];
        return flat_.InstancePath(InstanceId(slot_instance_[slot])) + "." +
               d.layout->connectors[slot - d.first_slot].decl->name;
      };
      if (set.size() == 1) {
        // An unconnected physical connector: its flows are zero.
        if (c0.type->is_signal) continue;
        for (size_t k = 0; k < c0.type->flows.size(); ++k) {
          VarId f = var_of(s0, static_cast<uint32_t>(c0.type->potentials.size() + k));
          FlatEquation eq;
          // f = 0 is an alias to a constant, unless the connector is conditional (an absent
          // one's equation goes: ResolveConditionalConnectors).
          if (deferred_ && !flat_.variables[f.value()].discrete && !conditional_slot_.count(s0)) {
            p.Var(f);  // the leaf, in its place (MakeBelowRoot)
            deferred_->AddZero(flat_.equations.size(), f);
          } else {
            eq.residual = p.Var(f);
          }
          eq.origin = EquationOrigin::kUnconnectedFlow;
          eq.instance = InstanceId(slot_instance_[s0]);
          eq.text = {TextRef::kUnconnected, f.value(), 0};  // "<connector>.<flow> = 0 (unconnected)"
          eq.loc = flat_.instances[slot_instance_[s0]].loc;
          flat_.equations.push_back(std::move(eq));
        }
        continue;
      }
      auto members = [&] {
        std::string list;
        for (uint32_t s : set) list += (list.empty() ? "" : ", ") + name_of(s);
        return list;
      };
      SourceLoc loc;
      for (uint32_t s : set) {
        if (slot_loc[s].known()) {
          loc = slot_loc[s];
          break;
        }
      }
      auto add = [&](ExprId residual, TextRef text) {
        FlatEquation eq;
        eq.residual = residual;  // invalid: deferred
        eq.origin = EquationOrigin::kConnection;
        eq.text = text;
        eq.loc = loc;
        flat_.equations.push_back(std::move(eq));
      };
      // "<a> = <b> (connection)": the connectors' variables are named <connector>.<potential>.
      // Connection equations between two continuous variables are aliases: not made (deferred_).
      auto continuous = [&](VarId a, VarId b) {
        return a != b && !flat_.variables[a.value()].discrete && !flat_.variables[b.value()].discrete;
      };
      auto equal = [&](VarId a, VarId b) {
        const TextRef text{TextRef::kEqual, a.value(), b.value()};
        if (deferred_ && continuous(a, b)) {
          // The leaves, in the order the made branch below makes them.
          p.Var(b);
          p.Var(a);
          deferred_->AddEqual(flat_.equations.size(), a, b);
          add(ExprId(), text);
        } else {
          const ExprId vb = p.Var(b);
          const ExprId va = p.Var(a);
          add(p.Sub(va, vb), text);
        }
      };
      if (c0.type->is_signal) {
        // Exactly one output drives the set; every input equals it.
        std::vector<uint32_t> outputs;
        for (uint32_t s : set) {
          const InstanceData& d = instance_data_[slot_instance_[s]];
          if (!d.layout->connectors[s - d.first_slot].type->is_input) outputs.push_back(s);
        }
        if (outputs.empty()) {
          throw ModelError(loc, "the signals " + members() + " are joined but no output drives them; connect an output (e.g. a Constant block's y)");
        }
        if (outputs.size() > 1) {
          throw ModelError(loc, "the outputs " + name_of(outputs[0]) + " and " + name_of(outputs[1]) +
                                    " are connected to each other; a signal has exactly one output");
        }
        for (uint32_t s : set) {
          if (s == outputs[0]) continue;
          CheckConnectedUnits(var_of(s, 0), name_of(s), var_of(outputs[0], 0), name_of(outputs[0]), loc);
          equal(var_of(s, 0), var_of(outputs[0], 0));
        }
        continue;
      }
      for (size_t k = 0; k < c0.type->potentials.size(); ++k) {
        for (size_t j = 1; j < set.size(); ++j) {
          equal(var_of(set[j], static_cast<uint32_t>(k)), var_of(s0, static_cast<uint32_t>(k)));
        }
      }
      for (size_t k = 0; k < c0.type->flows.size(); ++k) {
        uint32_t local = static_cast<uint32_t>(c0.type->potentials.size() + k);
        ExprId sum = p.Var(var_of(s0, local));
        if (deferred_ && set.size() == 2 && continuous(var_of(s0, local), var_of(set[1], local))) {
          p.Var(var_of(set[1], local));
          deferred_->AddSum(flat_.equations.size(), var_of(s0, local), var_of(set[1], local));
          sum = ExprId();
        } else {
          for (size_t j = 1; j < set.size(); ++j) sum = p.Add(sum, p.Var(var_of(set[j], local)));
        }
        // "sum of <flow> over {<connectors>} = 0 (connection)", named from the flow variables.
        const TextRef text{TextRef::kFlowSum, static_cast<uint32_t>(flat_.connection_vars.size()),
                           static_cast<uint32_t>(set.size())};
        for (uint32_t s : set) flat_.connection_vars.push_back(var_of(s, local));
        add(sum, text);
      }
    }
  }

  /// How many equations the connection sets make (below): potentials equal (a signal input
  /// equals its output), one sum per flow, an unconnected physical connector's flows zero.
  size_t ConnectionEquationCount(const std::vector<std::vector<uint32_t>>& sets) const {
    size_t n = 0;
    for (const auto& set : sets) {
      const InstanceData& d = instance_data_[slot_instance_[set[0]]];
      const ConnectorType& ct = *d.layout->connectors[set[0] - d.first_slot].type;
      if (ct.is_signal) {
        n += set.size() - 1;
      } else {
        n += ct.potentials.size() * (set.size() - 1) + ct.flows.size();
      }
    }
    return n;
  }

  /// Connected signals have one dimension when both declare a unit (a string compare first, so
  /// the cost per connection is small).
  void CheckConnectedUnits(VarId a, const std::string& a_name, VarId b, const std::string& b_name,
                           const SourceLoc& loc) {
    const std::string& ua = flat_.VariableUnit(a);
    const std::string& ub = flat_.VariableUnit(b);
    if (ua.empty() || ub.empty() || ua == ub) return;
    std::optional<Dimension> da = ModelUnits().DimensionOf(ua), db = ModelUnits().DimensionOf(ub);
    if (da && db && *da != *db) {
      throw ModelError(loc, "dimension mismatch in the connection of " + a_name + " [" + ua + "] to " + b_name +
                                " [" + ub + "]: " + DimensionText(*da) + " against " + DimensionText(*db));
    }
  }

  // -------------------------------------------------------------------------------------------
  // Model equations, outputs, parameter order

  void ModelEquations() {
    auto add = [&](const EquationDecl& d, EquationOrigin origin, std::vector<FlatEquation>* out) {
      FlatEquation eq;
      ExprId l = ModelExpr(*d.ast.lhs, d.text, d.loc, nullptr, true);
      ExprId r = ModelExpr(*d.ast.rhs, d.text, d.loc, nullptr, true);
      eq.residual = pool().Sub(l, r);
      eq.origin = origin;
      eq.text = flat_.Own(d.text);
      eq.loc = d.loc;
      out->push_back(std::move(eq));
    };
    for (const auto& d : spec_.equations) add(d, EquationOrigin::kModel, &flat_.equations);
    for (const auto* list : {&spec_.equations, &spec_.initial_equations}) {
      for (const auto& d : *list) ModelUnits().CheckEquation(*d.ast.lhs, *d.ast.rhs, d.text, d.loc);
    }
    for (const auto& w : spec_.whens) {
      FlatWhen fw;
      fw.condition = ModelExpr(*w.condition, w.text, w.loc, nullptr, true);
      for (const auto& st : w.statements) {
        ExprId target = ModelExpr(*ParseName(st.target, st.loc), st.text, st.loc, nullptr, true);
        if (pool().op(target) != Op::kVar) throw ModelError(st.loc, "'" + st.target + "' is not a variable, in '" + st.text + "'");
        VarId v(pool().node(target).a);
        ExprId value = ModelExpr(*st.value, st.text, st.loc, nullptr, true);
        if (st.is_reinit) {
          fw.reinits.emplace_back(v, value);
        } else {
          fw.assigns.emplace_back(v, value);
          flat_.variables[v.value()].discrete = true;
          model_assigns_ = true;
        }
      }
      fw.text = flat_.Own(w.text);
      fw.loc = w.loc;
      flat_.whens.push_back(std::move(fw));
      ModelUnits().CheckExpression(*w.condition, w.text, w.loc);
    }
    for (const auto& d : spec_.initial_equations) add(d, EquationOrigin::kInitial, &flat_.initial_equations);
  }

  /// The dimension check of the model's own equations and outputs: names are resolved as the
  /// model's expressions resolve them (a variable's or parameter's unit; "" for anything else).
  UnitChecker& ModelUnits() {
    if (!model_units_) {
      model_units_.emplace("model " + spec_.name, [this](const std::string& path) -> std::string {
        try {
          ExprId e = ModelExpr(*ParseName(path, SourceLoc()), path, SourceLoc(), nullptr, true);
          if (pool().op(e) == Op::kVar) return flat_.VariableUnit(VarId(pool().node(e).a));
          if (pool().op(e) == Op::kParam) return flat_.ParameterUnit(ParamId(pool().node(e).a));
        } catch (const ModelError&) {
          // time, pi, a loop index: not a variable or parameter.
        }
        return std::string();
      });
    }
    return *model_units_;
  }

  void Outputs() {
    std::unordered_map<std::string, SourceLoc> seen;
    for (const auto& o : spec_.outputs) {
      if (seen.count(o.text)) throw ModelError(o.loc, "output '" + o.text + "' is listed twice");
      seen[o.text] = o.loc;
      ExprId e = ModelExpr(*o.expr, o.text, o.loc, nullptr, true);
      flat_.outputs.push_back({o.text, e, o.loc, ModelUnits().UnitText(*o.expr, o.text, o.loc)});
    }
  }

  void OrderParameters() {
    // Depth-first topological order of the bindings, with cycle detection.
    const size_t n = flat_.parameters.size();
    std::vector<uint8_t> state(n, 0);
    std::vector<std::pair<uint32_t, std::vector<ExprId>>> stack;
    for (uint32_t s = 0; s < n; ++s) {
      if (state[s]) continue;
      stack.push_back({s, CollectLeaves(pool(), flat_.parameters[s].binding, kHasParam)});
      state[s] = 1;
      while (!stack.empty()) {
        auto& [id, deps] = stack.back();
        if (deps.empty()) {
          state[id] = 2;
          flat_.parameter_order.push_back(ParamId(id));
          stack.pop_back();
          continue;
        }
        uint32_t q = pool().node(deps.back()).a;
        deps.pop_back();
        if (state[q] == 1) {
          throw ModelError(flat_.parameters[q].loc, "the parameters' bindings form a cycle through " + flat_.ParameterName(ParamId(q)));
        }
        if (state[q] == 0) {
          state[q] = 1;
          stack.push_back({q, CollectLeaves(pool(), flat_.parameters[q].binding, kHasParam)});
        }
      }
    }
  }

  /// Every -p name must be a parameter: a usage error (exit 2) naming it, with the closest names,
  /// and for an element of a component array the indices it has.
  void CheckOverrides() {
    for (const auto& [name, value] : overrides_) {
      if (flat_.FindParameter(name)) continue;
      std::vector<std::string> model_names;
      for (const auto& p : spec_.parameters) model_names.push_back(p.name);
      std::vector<std::string> all;
      for (uint32_t k = 0; k < flat_.parameters.size(); ++k) all.push_back(flat_.ParameterName(ParamId(k)));
      auto close = ClosestNames(name, all);
      std::string range;
      if (size_t open = name.find('['); open != std::string::npos && open > 0) {
        const std::string array = name.substr(0, open);
        const ComponentArray* it = arrays_.Find(array);
        if (it && it->is_array) {
          range = " (" + array + " has elements " + array + "[1] to " + array + "[" +
                  std::to_string(it->count) + "])";
        }
      }
      throw UsageError(spec_.file + ": -p " + name + ": no parameter of that name in " + spec_.name + range +
                       (close.empty() ? "" : " (did you mean " + JoinNames(close) + "?)") +
                       " (model parameters: " + (model_names.empty() ? "none" : JoinNames(model_names)) +
                       "; component parameters are named like A.m)");
    }
  }

  const ModelSpec& spec_;
  const Library& library_;
  const ParameterOverrides& overrides_;
  std::optional<UnitChecker> model_units_;
  std::shared_ptr<Library> defines_ = std::make_shared<Library>();
  FlatSystem flat_;
  std::unordered_map<std::string, ParamId> model_param_;
  std::unordered_map<std::string, VarId> model_var_;
  ComponentIndex arrays_;  ///< the model's components by name (spec_'s names)
  double planned_bytes_ = 0;                ///< estimated memory of the components so far
  std::optional<MemoryBudget> budget_;      ///< read when the first count is checked
  std::unordered_map<const ComponentType*, std::unique_ptr<TypeLayout>> layouts_;
  std::unordered_map<const TypeLayout*, int32_t> names_of_;  ///< index in flat_.type_names
  std::vector<InstanceData> instance_data_;
  std::shared_ptr<DeferredAliases> deferred_;  ///< with defer_equations
  /// SureAliasShapes, by layout.
  std::unordered_map<const TypeLayout*, std::vector<uint32_t>> sure_shapes_;
  bool model_assigns_ = false;  ///< a model when-clause assigns a variable (made discrete)
  std::vector<uint32_t> slot_instance_;  ///< connector slot -> instance
  std::vector<uint32_t> parent_;         ///< union-find over connector slots
  /// The model's conditional connector slots -> their FlatSystem::conditional_connectors entry.
  std::unordered_map<uint32_t, size_t> conditional_slot_;
  std::vector<ExprId> scratch_;
  std::vector<const Modifier*> table_mod_;     ///< the current component's table values, by slot
  std::vector<InstanceTable> instance_tables_;  ///< the current instance's tables, by slot
  std::vector<double> model_values_;  ///< model parameters' values for structural expressions
  std::map<std::string, double> structural_;
  const ComponentSpec* current_component_ = nullptr;  ///< for messages about its type
  std::vector<const ComponentType*> laying_out_;      ///< types being laid out (cycle detection)
  const std::pair<std::string, double>* template_loop_ = nullptr;  ///< `i` in a part's modifiers
  std::vector<uint8_t> param_state_;  ///< model parameters: 0 new, 1 being evaluated, 2 done
  std::vector<double> param_value_;
};

}  // namespace

FlatSystem Flatten(const ModelSpec& spec, const Library& library, const ParameterOverrides& overrides,
                   bool defer_equations) {
  // Vectors and matrices become scalars first (core/lang/arrays.h); a model without arrays is used as is.
  std::optional<ModelSpec> scalar = ScalarModel(spec, library);
  return Flattener(scalar ? *scalar : spec, library, overrides, defer_equations).Run();
}

namespace {
/// A table's first column (a vector table: its elements) must increase strictly: interpolation
/// and time events need ordered, distinct abscissas.
void CheckTables(const FlatSystem& flat, const std::vector<double>& values) {
  for (const FlatTable& t : flat.tables) {
    for (uint32_t r = 1; r < t.rows; ++r) {
      const double prev = values[t.first.value() + static_cast<size_t>(r - 1) * t.cols];
      const double x = values[t.first.value() + static_cast<size_t>(r) * t.cols];
      const bool jump = r - 1 < t.jumps.size() && t.jumps[r - 1];
      if (jump ? x == prev : x > prev) continue;
      std::ostringstream msg;
      const FlatInstance& inst = flat.instances[t.instance.value()];
      msg << t.name << " (" << inst.type->name << "): row " << r + 1 << " has " << (t.cols > 1 ? "abscissa " : "")
          << x;
      if (jump) {
        msg << ", but the model was built with a jump there (the same time as row " << r
            << "); build the model again with the new table";
      } else {
        msg << ", not greater than row " << r << "'s " << prev << "; the "
            << (t.cols > 1 ? "first column of a table" : "elements of a table") << " must increase strictly"
            << (t.jumps.empty() ? "" : " (a time given twice, a jump, is fixed when the model is built)");
      }
      throw ModelError(t.loc, msg.str());
    }
  }
}
}  // namespace

std::vector<double> EvaluateParameters(const FlatSystem& flat, const ParameterOverrides& overrides) {
  const ExprPool& pool = *flat.pool;
  std::vector<double> values(flat.parameters.size(), 0.0);
  std::vector<const double*> override_of(flat.parameters.size(), nullptr);
  if (!overrides.empty()) {
    for (const auto& [name, value] : overrides) {
      std::optional<ParamId> id = flat.FindParameter(name);
      if (!id) throw ModelError(flat.file + ": -p " + name + ": no parameter of that name");
      override_of[id->value()] = &value;
    }
  }
  // A parameter that shaped the structure (count:, indices) keeps the value it was built with.
  for (const auto& [name, value] : overrides) {
    auto it = flat.structural.find(name);
    if (it != flat.structural.end() && it->second != value) {
      std::ostringstream msg;
      msg << flat.file << ": -p " << name << "=" << value << ": " << name
          << " shapes the model's structure (a count or a connection index) and the model was built with "
          << name << " = " << it->second << "; build the model again with the new value";
      throw ModelError(msg.str());
    }
  }
  LeafValues lv;
  lv.params = values.data();
  for (ParamId id : flat.parameter_order) {
    const FlatParameter& p = flat.parameters[id.value()];
    double v = override_of[id.value()] ? *override_of[id.value()]
               : pool.IsConst(p.binding) ? pool.ConstValue(p.binding)
                                         : Evaluate(pool, p.binding, lv);
    // The messages below name it; the names are made only for them.
    auto where = [&] { return override_of[id.value()] ? flat.file + ": -p " + flat.ParameterName(id) : ""; };
    auto fail = [&](const std::string& msg) {
      if (!where().empty()) throw ModelError(where() + ": " + msg);
      throw ModelError(p.loc, msg);
    };
    auto what = [&] {
      const std::string name = flat.ParameterName(id);
      if (!p.instance.valid()) return name;
      const FlatInstance& inst = flat.instances[p.instance.value()];
      const std::string& doc = flat.ParameterDoc(id);
      const std::string& unit = flat.ParameterUnit(id);
      return name + " (" + inst.type->name + "." + name.substr(flat.InstancePath(p.instance).size() + 1) + (doc.empty() ? "" : ": " + doc) +
             (unit.empty() ? "" : " [" + unit + "]") + ")";
    };
    if (!std::isfinite(v)) fail(what() + " is " + std::to_string(v) + "; a parameter must be a finite number");
    auto num = [](double x) {
      std::ostringstream s;
      s << x;
      return s.str();
    };
    if (v < p.min) fail(what() + " = " + num(v) + " is below its minimum " + num(p.min));
    if (v > p.max) fail(what() + " = " + num(v) + " is above its maximum " + num(p.max));
    values[id.value()] = v;
  }
  CheckTables(flat, values);
  return values;
}

}  // namespace momenta
