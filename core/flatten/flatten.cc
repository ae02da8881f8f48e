// Flattening: a model spec and the component library in, one flat system out. The driver runs
// the jobs in order over one shared record (flatten_context.h): the model's parameters and
// variables (model_scope.h), its components (instances.h, laying out each type once:
// type_layout.h), its connections (model_connections.h), then its own equations, when-clauses
// and outputs, the order of the parameters' bindings and the check of the -p overrides here.

#include "core/flatten/flatten.h"

#include <cmath>
#include <optional>
#include <sstream>
#include <unordered_map>

#include "core/base/error.h"
#include "core/base/messages.h"
#include "core/expr/expr_eval.h"
#include "core/flatten/build_time_values.h"
#include "core/flatten/connection_graph.h"
#include "core/flatten/deferred_aliases.h"
#include "core/flatten/flatten_context.h"
#include "core/flatten/free_parameters.h"
#include "core/flatten/instances.h"
#include "core/flatten/model_connections.h"
#include "core/flatten/model_scope.h"
#include "core/flatten/outers.h"
#include "core/flatten/type_layout.h"
#include "core/lang/arrays.h"
#include "core/lang/parser.h"
#include "core/lang/records.h"

namespace momenta {

namespace {

using flatten_internal::FlattenContext;
using flatten_internal::InstanceBuilder;
using flatten_internal::ModelConnections;
using flatten_internal::ModelScope;
using flatten_internal::TypeLayoutBuilder;

class Flattener {
 public:
  Flattener(const ModelSpec& spec, const Library& library, const ParameterOverrides& overrides,
            bool defer_equations)
      : context_(spec, library, overrides, defer_equations),
        scope_(&context_),
        layouts_(&context_),
        instances_(&context_, &layouts_, &scope_) {}

  FlatSystem Run() {
    scope_.DeclareParameters();
    scope_.DeclareVariables();
    instances_.Components();
    flatten_internal::ResolveOuters(&context_);
    ModelConnections(&context_, &scope_).Run();
    ModelEquations();
    Outputs();
    OrderParameters();
    CheckOverrides();
    flatten_internal::MakeFreeParametersVariables(&context_);
    flatten_internal::ResolveConnectionGraph(&context_);
    CheckBuildTimeValues(context_.flat);
    CheckWhenConditions(context_.flat);
    FlatSystem& flat = context_.flat;
    flat.defines = context_.defines;  // instances point into these types
    if (context_.deferred && !context_.deferred->empty()) {
      if (model_assigns_) context_.deferred->MakeDiscrete(&flat);
      context_.deferred->Keep(layouts_.TakeLayouts());
      flat.deferred = std::move(context_.deferred);
    }
    return std::move(flat);
  }

 private:
  ExprPool& pool() { return context_.pool(); }

  /// The model's own equations, when-clauses and initial equations, with their dimensions
  /// checked.
  void ModelEquations() {
    const ModelSpec& spec = context_.spec;
    FlatSystem& flat = context_.flat;
    auto add = [&](const EquationDecl& equation, EquationOrigin origin, std::vector<FlatEquation>* out) {
      FlatEquation eq;
      ExprId l = scope_.Expr(*equation.ast.lhs, equation.text, equation.loc, nullptr, true);
      ExprId r = scope_.Expr(*equation.ast.rhs, equation.text, equation.loc, nullptr, true);
      eq.residual = pool().Sub(l, r);
      eq.origin = origin;
      eq.text = flat.Own(equation.text);
      eq.loc = equation.loc;
      out->push_back(std::move(eq));
    };
    for (const auto& equation : spec.equations) add(equation, EquationOrigin::kModel, &flat.equations);
    for (const auto* list : {&spec.equations, &spec.initial_equations}) {
      for (const auto& equation : *list) scope_.Units().CheckEquation(*equation.ast.lhs, *equation.ast.rhs, equation.text, equation.loc);
    }
    for (const auto& w : spec.whens) ModelWhen(w);
    for (const auto& equation : spec.initial_equations) add(equation, EquationOrigin::kInitial, &flat.initial_equations);
  }

  /// A when-clause of the model: a variable it assigns becomes discrete.
  void ModelWhen(const WhenDecl& w) {
    FlatSystem& flat = context_.flat;
    FlatWhen fw;
    fw.condition = scope_.Expr(*w.condition, w.text, w.loc, nullptr, true);
    for (const auto& statement : w.statements) {
      ExprId target = scope_.Expr(*ParseName(statement.target, statement.loc), statement.text, statement.loc, nullptr, true);
      if (pool().op(target) != Op::kVar) {
        throw ModelError(statement.loc, "'" + statement.target + "' is not a variable, in '" + statement.text + "'");
      }
      VarId v(pool().node(target).a);
      ExprId value = scope_.Expr(*statement.value, statement.text, statement.loc, nullptr, true);
      if (statement.is_reinit) {
        fw.reinits.emplace_back(v, value);
      } else {
        fw.assigns.emplace_back(v, value);
        flat.variables[v.value()].discrete = true;
        model_assigns_ = true;
      }
    }
    fw.text = flat.Own(w.text);
    fw.loc = w.loc;
    flat.whens.push_back(std::move(fw));
    scope_.Units().CheckExpression(*w.condition, w.text, w.loc);
  }

  void Outputs() {
    std::unordered_map<std::string, SourceLoc> seen;
    for (const auto& o : context_.spec.outputs) {
      if (seen.count(o.text)) throw ModelError(o.loc, "output '" + o.text + "' is listed twice");
      seen[o.text] = o.loc;
      ExprId e = scope_.Expr(*o.expr, o.text, o.loc, nullptr, true);
      context_.flat.outputs.push_back({o.text, e, o.loc, scope_.Units().UnitText(*o.expr, o.text, o.loc)});
    }
  }

  /// Every binding's parameters before it (FlatSystem::parameter_order): a depth-first
  /// topological order of the bindings, with cycle detection.
  void OrderParameters() {
    FlatSystem& flat = context_.flat;
    const size_t n = flat.parameters.size();
    std::vector<uint8_t> state(n, 0);
    std::vector<std::pair<uint32_t, std::vector<ExprId>>> stack;
    for (uint32_t s = 0; s < n; ++s) {
      if (state[s]) continue;
      stack.push_back({s, CollectLeaves(pool(), flat.parameters[s].binding, kHasParam)});
      state[s] = 1;
      while (!stack.empty()) {
        auto& [id, deps] = stack.back();
        if (deps.empty()) {
          state[id] = 2;
          flat.parameter_order.push_back(ParamId(id));
          stack.pop_back();
          continue;
        }
        uint32_t q = pool().node(deps.back()).a;
        deps.pop_back();
        if (state[q] == 1) {
          throw ModelError(flat.parameters[q].loc, "the parameters' bindings form a cycle through " + flat.ParameterName(ParamId(q)));
        }
        if (state[q] == 0) {
          state[q] = 1;
          stack.push_back({q, CollectLeaves(pool(), flat.parameters[q].binding, kHasParam)});
        }
      }
    }
  }

  /// Every -p name must be a parameter: a usage error (exit 2) naming it, with the closest names,
  /// and for an element of a component array the indices it has.
  void CheckOverrides() {
    const ModelSpec& spec = context_.spec;
    const FlatSystem& flat = context_.flat;
    for (const auto& [name, value] : context_.overrides) {
      if (flat.FindParameter(name)) continue;
      std::vector<std::string> model_names;
      for (const auto& p : spec.parameters) model_names.push_back(p.name);
      std::vector<std::string> all;
      for (uint32_t k = 0; k < flat.parameters.size(); ++k) all.push_back(flat.ParameterName(ParamId(k)));
      auto close = ClosestNames(name, all);
      std::string range;
      if (size_t open = name.find('['); open != std::string::npos && open > 0) {
        const std::string array = name.substr(0, open);
        const flatten_internal::ComponentArray* it = context_.components.Find(array);
        if (it && it->is_array) {
          range = " (" + array + " has elements " + array + "[1] to " + array + "[" +
                  std::to_string(it->count) + "])";
        }
      }
      throw UsageError(spec.file + ": -p " + name + ": no parameter of that name in " + spec.name + range +
                       (close.empty() ? "" : " (did you mean " + JoinNames(close) + "?)") +
                       " (model parameters: " + (model_names.empty() ? "none" : JoinNames(model_names)) +
                       "; component parameters are named like A.m)");
    }
  }

  FlattenContext context_;
  ModelScope scope_;
  TypeLayoutBuilder layouts_;
  InstanceBuilder instances_;
  bool model_assigns_ = false;  ///< a model when-clause assigns a variable (made discrete)
};

}  // namespace

namespace {
/// The model's own connectors, records and functions (`define:`, `uses:` files) over `library`,
/// its connectors' records expanded there; null when it has none.
std::shared_ptr<Library> ModelLibrary(const ModelSpec& spec, const Library& library) {
  if (!spec.own || spec.own->empty()) return nullptr;
  auto own = std::make_shared<Library>();
  own->SetBase(&library);
  own->AddRecordsAndFunctions(*spec.own);
  for (const std::string& name : spec.own->ConnectorNames()) {
    own->AddConnector(ScalarForm(ExpandRecords(*spec.own->FindConnector(name), *own)));
  }
  return own;
}
}  // namespace

FlatSystem Flatten(const ModelSpec& spec, const Library& library, const ParameterOverrides& overrides,
                   bool defer_equations) {
  const std::shared_ptr<Library> own = ModelLibrary(spec, library);
  const Library& scope = own ? *own : library;
  // Vectors and matrices become scalars first (core/lang/arrays.h); a model without arrays is used as is.
  std::optional<ModelSpec> scalar = ScalarModel(spec, scope);
  FlatSystem flat = Flattener(scalar ? *scalar : spec, scope, overrides, defer_equations).Run();
  flat.model_library = own;
  return flat;
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
  // Every name is checked before any value (the first error is an unknown name, if any).
  std::vector<std::pair<ParamId, const ParameterOverrides::value_type*>> given;  // in the overrides' order
  for (const auto& entry : overrides) {
    std::optional<ParamId> id = flat.FindParameter(entry.first);
    if (!id) throw ModelError(flat.file + ": -p " + entry.first + ": no parameter of that name");
    override_of[id->value()] = &entry.second;
    given.emplace_back(*id, &entry);
  }
  // A parameter that shaped the structure (count:, indices) keeps the value it was built with.
  for (const auto& [id, entry] : given) {
    const auto& [name, value] = *entry;
    const double* built = flat.structural.Find(id);
    if (built != nullptr && *built != value) {
      std::ostringstream msg;
      msg << flat.file << ": -p " << name << "=" << value << ": " << name
          << " shapes the model's structure (a count or a connection index) and the model was built with "
          << name << " = " << *built << "; build the model again with the new value";
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
    // Integer and Boolean parameters take whole numbers and truth values only (-p: exit 2).
    const char* kind = p.type == ValueType::kInteger && v != std::floor(v)             ? "an Integer parameter takes whole numbers only"
                       : p.type == ValueType::kBoolean && v != 0.0 && v != 1.0 ? "a Boolean parameter takes true, false, 1 or 0 only"
                                                                                : nullptr;
    if (kind && override_of[id.value()]) throw UsageError(where() + "=" + num(v) + ": " + kind);
    if (kind) fail(what() + " = " + num(v) + ": " + kind);
    if (v < p.min) fail(what() + " = " + num(v) + " is below its minimum " + num(p.min));
    if (v > p.max) fail(what() + " = " + num(v) + " is above its maximum " + num(p.max));
    values[id.value()] = v;
  }
  CheckTables(flat, values);
  return values;
}

}  // namespace momenta
