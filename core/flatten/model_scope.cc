// The model scope: the model's parameters and variables, the names its expressions use, the
// structural values the model is built with, and its expressions lowered into the pool
// (ModelScope::Lowering).

#include "core/flatten/model_scope.h"

#include <cmath>

#include "core/base/error.h"
#include "core/base/messages.h"
#include "core/expr/expr_eval.h"
#include "core/flatten/type_layout.h"
#include "core/lang/parser.h"

namespace momenta::flatten_internal {

void ModelScope::DeclareParameters() {
  const ModelSpec& spec = context_.spec;
  FlatSystem& flat = context_.flat;
  for (const auto& p : spec.parameters) {
    if (parameters_.count(p.name)) throw ModelError(p.loc, "parameter " + p.name + " is declared twice");
    FlatParameter fp;
    fp.name = flat.Own(p.name);
    fp.type = p.type;
    fp.evaluate = p.evaluate;
    if (p.min) fp.min = *p.min;
    if (p.max) fp.max = *p.max;
    fp.unit = flat.Own(p.unit);
    fp.doc = flat.Own(p.doc);
    fp.loc = p.loc;
    parameters_[p.name] = ParamId(flat.parameters.size());
    flat.parameters.push_back(fp);
  }
  for (size_t k = 0; k < spec.parameters.size(); ++k) {
    const auto& p = spec.parameters[k];
    flat.parameters[k].binding = Expr(*p.value, p.value_text, p.loc, nullptr, false);
  }
}

void ModelScope::DeclareVariables() {
  FlatSystem& flat = context_.flat;
  for (const auto& v : context_.spec.variables) {
    if (Declares(v.name)) throw ModelError(v.loc, v.name + " is declared twice");
    FlatVariable fv;
    fv.name = flat.Own(v.name);
    fv.type = v.type;
    fv.fixed = v.fixed;
    fv.nominal = v.nominal;
    fv.state_priority = v.state_priority;
    fv.loc = v.loc;
    flat.model_variable_units.push_back(flat.Own(v.unit));
    fv.start = v.start ? StartExpr(*v.start, v.loc, nullptr) : ExprId();
    fv.discrete = v.type != ValueType::kReal;
    variables_[v.name] = VarId(flat.variables.size());
    flat.variables.push_back(fv);
  }
}

double ModelScope::StructuralValue(const Ast& a, const std::string& text, const SourceLoc& loc, const LoopIndex* loop) {
  ExprPool& pool = context_.pool();
  const ModelSpec& spec = context_.spec;
  ExprId e = Expr(a, text, loc, loop, false);
  if (!pool.IsParamOnly(e)) throw ModelError(loc, "'" + text + "' must be a constant expression of parameters");
  if (pool.IsConst(e)) return pool.ConstValue(e);
  if (structural_values_.empty() && !spec.parameters.empty()) {
    structural_values_.resize(spec.parameters.size());
    for (size_t k = 0; k < spec.parameters.size(); ++k) structural_values_[k] = ParameterValue(ParamId(k));
  }
  for (ExprId leaf : CollectLeaves(pool, e, kHasParam)) {
    uint32_t id = pool.node(leaf).a;
    if (id >= spec.parameters.size()) {
      throw ModelError(loc, "'" + text + "' shapes the model's structure, so it may use model parameters only");
    }
    context_.flat.structural.Set(ParamId(id), structural_values_[id]);
  }
  LeafValues lv;
  lv.params = structural_values_.data();
  return Evaluate(pool, e, lv);
}

double ModelScope::ParameterValue(ParamId id) {
  ExprPool& pool = context_.pool();
  const FlatSystem& flat = context_.flat;
  const size_t n = context_.spec.parameters.size();
  if (param_state_.size() != n) {
    param_state_.assign(n, 0);
    param_value_.assign(n, 0.0);
  }
  std::vector<std::pair<uint32_t, bool>> stack{{id.value(), false}};
  while (!stack.empty()) {
    auto [q, expanded] = stack.back();
    stack.pop_back();
    if (param_state_[q] == 2) continue;
    const FlatParameter& p = flat.parameters[q];
    auto ov = context_.overrides.find(flat.ParameterName(ParamId(q)));
    if (ov != context_.overrides.end()) {
      param_value_[q] = ov->second;
      param_state_[q] = 2;
      continue;
    }
    std::vector<ExprId> deps = CollectLeaves(pool, p.binding, kHasParam);
    if (!expanded) {
      if (param_state_[q] == 1) {
        throw ModelError(p.loc, "the parameters' bindings form a cycle through " + flat.ParameterName(ParamId(q)));
      }
      param_state_[q] = 1;
      stack.push_back({q, true});
      for (ExprId pe : deps) {
        uint32_t dependency = pool.node(pe).a;
        if (param_state_[dependency] == 1) {
          throw ModelError(flat.parameters[dependency].loc,
                           "the parameters' bindings form a cycle through " + flat.ParameterName(ParamId(dependency)));
        }
        if (param_state_[dependency] == 0) stack.push_back({dependency, false});
      }
      continue;
    }
    LeafValues lv;
    lv.params = param_value_.data();
    param_value_[q] = Evaluate(pool, p.binding, lv);
    param_state_[q] = 2;
  }
  return param_value_[id.value()];
}

double ModelScope::StructuralWhole(const Ast& a, const std::string& text, const SourceLoc& loc, const LoopIndex* loop,
                                   const std::string& what) {
  double v = StructuralValue(a, text, loc, loop);
  if (!std::isfinite(v) || v != std::floor(v)) {
    throw ModelError(loc, what + " must be a whole number, found " + NumberText(v));
  }
  return v;
}

ExprId ModelScope::Name(const Ast& a, const SourceLoc& base, const LoopIndex* loop, bool allow_variables,
                        const std::string& text) {
  ExprPool& pool = context_.pool();
  const ModelSpec& spec = context_.spec;
  SourceLoc loc = base.Shifted(a.column);
  const auto& first = a.path[0];
  auto variable = [&](uint32_t v, const std::string& name) {
    if (!allow_variables) throw ModelError(loc, "'" + name + "' is a variable; only parameters may be used in '" + text + "'");
    return pool.Var(VarId(v));
  };
  if (a.path.size() == 1 && !first.index) {
    if (loop && first.name == loop->first) return pool.Const(loop->second);
    auto mp = parameters_.find(first.name);
    if (mp != parameters_.end()) return pool.Param(mp->second);
    auto mv = variables_.find(first.name);
    if (mv != variables_.end()) return variable(mv->second.value(), first.name);
    if (first.name == "time") {
      if (!allow_variables) throw ModelError(loc, "time cannot be used in '" + text + "'");
      return pool.Time();
    }
    if (first.name == "pi") return pool.Const(M_PI);
  }
  // An instance path: first segment is a component (or an element of an array).
  const ComponentArray* arr = context_.components.Find(first.name);
  if (!arr && a.path.size() > 1) {  // a field of the model's own record variable: R.T[1,1]
    auto mv = variables_.find(a.PathText());
    if (mv != variables_.end()) return variable(mv->second.value(), a.PathText());
  }
  if (!arr) {
    std::vector<std::string> names;
    for (const auto& p : spec.parameters) names.push_back(p.name);
    for (const auto& c : spec.components) names.push_back(c.name);
    for (const auto& v : spec.variables) names.push_back(v.name);
    auto close = ClosestNames(first.name, names);
    throw ModelError(loc, "unknown name '" + a.PathText() + "' in '" + text + "'" +
                              (close.empty() ? "" : " (did you mean " + JoinNames(close) + "?)") +
                              " (valid names: " + JoinNames(names) + ")");
  }
  uint32_t inst = ElementOf(*arr, first, loc, loop, text);
  const InstanceData& data = context_.instance_data[inst];
  std::string local;
  for (size_t k = 1; k < a.path.size(); ++k) {
    if (k > 1) local += ".";
    local += a.path[k].name;
    if (a.path[k].index) {  // an element of a part array inside a composite: arm.links[2].phi
      const double i = SubscriptValue(*a.path[k].index, loc, loop);
      local += '[';
      local += NumberText(i);
      local += ']';
    }
  }
  if (local.empty()) throw ModelError(loc, "'" + a.PathText() + "' names a component, not one of its variables");
  auto v = data.layout->var_index.find(local);
  if (v != data.layout->var_index.end()) return variable(data.first_var.value() + v->second, a.PathText());
  auto p = data.layout->param_index.find(local);
  if (p != data.layout->param_index.end()) {
    return pool.Param(ParamId(data.first_param.value() + p->second));
  }
  auto names = data.layout->LocalNames();
  throw ModelError(loc, context_.flat.InstancePath(InstanceId(inst)) + " (" + data.layout->type->name +
                            ") has no variable or parameter '" + local + "' (valid names: " +
                            JoinNames(names) + ")");
}

double ModelScope::SubscriptValue(const Ast& a, const SourceLoc& loc, const LoopIndex* loop) {
  if (std::optional<double> v = WholeSum(a, loop)) return *v;
  return StructuralWhole(a, AstToString(a), loc, loop, "an index");
}

std::optional<double> ModelScope::WholeSum(const Ast& a, const LoopIndex* loop) {
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

uint32_t ModelScope::ElementOf(const ComponentArray& arr, const NameSegment& seg, const SourceLoc& loc,
                               const LoopIndex* loop, const std::string& text) {
  if (!arr.is_array) {
    if (seg.index) throw ModelError(loc, seg.name + " is not an array (it has no count:), in '" + text + "'");
    return arr.first_instance;
  }
  if (!seg.index) {
    throw ModelError(loc, seg.name + " is an array of " + std::to_string(arr.count) +
                              " components; name one element, e.g. " + seg.name + "[1]");
  }
  double k = SubscriptValue(*seg.index, loc, loop);
  if (k < 1 || k > arr.count) {
    throw ModelError(loc, seg.name + "[" + NumberText(k) + "] is out of range 1.." +
                              std::to_string(arr.count) + " in '" + text + "'");
  }
  return arr.first_instance + arr.stride * static_cast<uint32_t>(k - 1);
}

class ModelScope::Lowering {
 public:
  using Node = ExprId;
  /// The second operand first: the order in which the model's expressions have always been made
  /// (written as one call, pool.Binary(op, lower(0), lower(1)), whose arguments g++ evaluates
  /// right to left); the pool's node ids, and so the compiled programs, keep it.
  static constexpr bool kSecondOperandFirst = true;

  Lowering(ModelScope* scope, std::string text, const SourceLoc& loc, const LoopIndex* loop, bool allow_variables)
      : scope_(*scope), pool_(scope->context_.pool()), text_(std::move(text)), loc_(loc), loop_(loop),
        allow_variables_(allow_variables) {}

  Node Constant(double value) { return pool_.Const(value); }
  Node Name(const Ast& a) { return scope_.Name(a, loc_, loop_, allow_variables_, text_); }
  Node Unary(Op op, Node x) { return pool_.Unary(op, x); }
  Node Negate(Node x) { return pool_.Neg(x); }
  Node Binary(Op op, Node x, Node y) { return pool_.Binary(op, x, y); }
  Node If(Node c, Node x, Node y) { return pool_.If(c, x, y); }
  Node NoEvent(Node x) { return pool_.NoEvent(x); }
  Node Der(Node x) { return TimeDerivative(&pool_, x); }
  Node Initial() { return pool_.Initial(); }
  bool IsVariable(Node x) const { return pool_.op(x) == Op::kVar; }
  Node Pre(Node x) { return pool_.Pre(VarId(pool_.node(x).a)); }
  /// The model has no tables of its own; a parameter's value or a start value may call nothing
  /// but the pool's functions and noEvent().
  void CheckCall(const Ast& a) const {
    if (a.op == "noEvent") return;
    if (a.op == "interpolate" || a.op == "timeTable" || a.op == "booleanTable") {
      Fail(a, a.op + "() reads a table of a component type, in its equations; the model's own " +
                  "equations cannot (use a CombiTimeTable, or a type with the table), in '" + text_ + "'");
    }
    if (!allow_variables_) Fail(a, a.op + "() cannot be used in '" + text_ + "'");
  }
  std::optional<Node> TableCall(const Ast&) { return std::nullopt; }
  const std::string& text() const { return text_; }
  std::string OfOwner() const { return std::string(); }
  [[noreturn]] void Fail(const Ast& at, const std::string& message) const {
    throw ModelError(loc_.Shifted(at.column), message);
  }

 private:
  ModelScope& scope_;
  ExprPool& pool_;
  const std::string text_;  ///< as messages quote it
  const SourceLoc loc_;
  const LoopIndex* loop_;
  const bool allow_variables_;
};

ExprId ModelScope::Expr(const Ast& a, const std::string& text, const SourceLoc& loc, const LoopIndex* loop,
                        bool allow_variables) {
  // A number (most modifiers' values) needs no walk and no text for messages.
  if (a.kind == Ast::Kind::kNumber || a.kind == Ast::Kind::kBool) return context_.pool().Const(a.number);
  Lowering scope(this, Excerpt(text, 0), loc, loop, allow_variables);  // messages quote the text
  return Lower(a, &scope);
}

ExprId ModelScope::StartExpr(const Ast& a, const SourceLoc& loc, const LoopIndex* loop) {
  if (a.kind == Ast::Kind::kNumber || a.kind == Ast::Kind::kBool) return context_.pool().Const(a.number);
  return Expr(a, AstToString(a), loc, loop, false);
}

UnitChecker& ModelScope::Units() {
  if (!units_) {
    units_.emplace("model " + context_.spec.name, [this](const std::string& path) -> std::string {
      ExprPool& pool = context_.pool();
      try {
        ExprId e = Expr(*ParseName(path, SourceLoc()), path, SourceLoc(), nullptr, true);
        if (pool.op(e) == Op::kVar) return context_.flat.VariableUnit(VarId(pool.node(e).a));
        if (pool.op(e) == Op::kParam) return context_.flat.ParameterUnit(ParamId(pool.node(e).a));
      } catch (const ModelError&) {
        // time, pi, a loop index: not a variable or parameter.
      }
      return std::string();
    });
  }
  return *units_;
}

}  // namespace momenta::flatten_internal
