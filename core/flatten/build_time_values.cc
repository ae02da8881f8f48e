// The build-time check of non-finite operations on constants (build_time_values.h).

#include "core/flatten/build_time_values.h"

#include <cmath>
#include <string>
#include <vector>

#include "core/base/error.h"
#include "core/base/messages.h"
#include "core/expr/expr_print.h"
#include "core/expr/ops.h"

namespace momenta {

namespace {

/// The innermost operation under `e` whose value is not finite: the node marked singular none
/// of whose operands is.
ExprId InnermostSingular(const ExprPool& pool, ExprId e) {
  for (;;) {
    const Node& n = pool.node(e);
    const int arity = Arity(n.op);
    const uint32_t kids[3] = {n.a, n.b, n.c};
    ExprId next;
    for (int k = 0; k < arity && !next.valid(); ++k) {
      if (pool.IsSingular(ExprId(kids[k]))) next = ExprId(kids[k]);
    }
    if (!next.valid()) return e;
    e = next;
  }
}

/// "division by zero in '1/0'" or "'1e+308*10' is inf", for the singular part of `e`.
std::string Describe(const FlatSystem& flat, ExprId e) {
  const ExprPool& pool = *flat.pool;
  const ExprId s = InnermostSingular(pool, e);
  const std::string text = "'" + ToString(pool, s, flat.Namer()) + "'";
  const Node& n = pool.node(s);
  if (n.op == Op::kDiv && pool.IsConst(ExprId(n.b), 0.0)) return "division by zero in " + text;
  const double v = Arity(n.op) == 1 ? ApplyUnary(n.op, pool.ConstValue(ExprId(n.a)))
                                    : ApplyBinary(n.op, pool.ConstValue(ExprId(n.a)), pool.ConstValue(ExprId(n.b)));
  return text + " is " + (std::isnan(v) ? std::string("NaN") : NumberText(v));
}

void CheckEquations(const FlatSystem& flat, const std::vector<FlatEquation>& equations) {
  for (const FlatEquation& eq : equations) {
    if (!eq.residual.valid() || !flat.pool->IsSingular(eq.residual)) continue;
    SourceLoc loc = eq.loc;
    if (!loc.known() && eq.instance.valid()) loc = flat.instances[eq.instance.value()].loc;
    throw ModelError(loc, Describe(flat, eq.residual) + ", in equation " + flat.DescribeEquation(eq) +
                              ": a value known at build time must be a finite number");
  }
}

/// Whether `e` is a truth value: a relation, and/or/not, true or false, initial(), or a Boolean
/// variable, pre-value or parameter; an if-expression is taken as one.
bool IsTruth(const FlatSystem& flat, ExprId e) {
  const ExprPool& pool = *flat.pool;
  const Node& n = pool.node(e);
  switch (n.op) {
    case Op::kInitial: return true;
    case Op::kVar:
    case Op::kPre: return flat.variables[n.a].type == ValueType::kBoolean;
    case Op::kParam: return flat.parameters[n.a].type == ValueType::kBoolean;
    case Op::kIf: return true;  // (its branches are not followed: an elseif chain may be deep)
    default: return pool.IsTruthValued(e);
  }
}

/// A number that is not whole where it becomes the value of `e` (an operand of +, -, * or unary
/// minus, a branch of an if-expression, min or max): what an Integer defined by `e` would take.
/// Conditions and function arguments are not followed: their numbers are not the value.
bool NonWholeValue(const ExprPool& pool, ExprId e, double* value) {
  std::vector<ExprId> todo{e};
  while (!todo.empty()) {
    const ExprId id = todo.back();
    todo.pop_back();
    const Node& n = pool.node(id);
    switch (n.op) {
      case Op::kConst:
        if (std::isfinite(n.value()) && n.value() != std::floor(n.value())) {
          *value = n.value();
          return true;
        }
        break;
      case Op::kAdd: case Op::kSub: case Op::kMul: case Op::kMin: case Op::kMax:
        todo.push_back(ExprId(n.a));
        todo.push_back(ExprId(n.b));
        break;
      case Op::kNeg: todo.push_back(ExprId(n.a)); break;
      case Op::kIf:
        todo.push_back(ExprId(n.b));
        todo.push_back(ExprId(n.c));
        break;
      default: break;
    }
  }
  return false;
}

/// The Integer variable an equation `k = e` (residual k - e or e - k) defines, and e.
bool IntegerDefinition(const FlatSystem& flat, ExprId residual, VarId* k, ExprId* value) {
  const ExprPool& pool = *flat.pool;
  const Node& n = pool.node(residual);
  if (n.op != Op::kSub) return false;
  for (const auto& [var, other] : {std::pair{n.a, n.b}, std::pair{n.b, n.a}}) {
    const Node& v = pool.node(ExprId(var));
    if (v.op == Op::kVar && flat.variables[v.a].type == ValueType::kInteger) {
      *k = VarId(v.a);
      *value = ExprId(other);
      return true;
    }
  }
  return false;
}

std::string NotWhole(const FlatSystem& flat, VarId k, double value) {
  return "the Integer " + flat.VariableName(k) + " is given " + NumberText(value);
}

}  // namespace

void CheckIntegerValues(const FlatSystem& flat) {
  const char* const kWhole = ": an Integer takes whole numbers only (a Real value needs a Real variable)";
  double value = 0;
  for (const FlatEquation& eq : flat.equations) {
    VarId k;
    ExprId e;
    if (!eq.residual.valid() || !IntegerDefinition(flat, eq.residual, &k, &e)) continue;
    if (!NonWholeValue(*flat.pool, e, &value)) continue;
    SourceLoc loc = eq.loc;
    if (!loc.known() && eq.instance.valid()) loc = flat.instances[eq.instance.value()].loc;
    throw ModelError(loc, NotWhole(flat, k, value) + " by '" + flat.EquationText(eq) + "'" + kWhole);
  }
  for (const FlatWhen& w : flat.whens) {
    for (const auto& [v, e] : w.assigns) {
      if (flat.variables[v.value()].type != ValueType::kInteger || !NonWholeValue(*flat.pool, e, &value)) continue;
      throw ModelError(w.loc, NotWhole(flat, v, value) + " in when-clause '" + flat.WhenText(w) + "'" + kWhole);
    }
  }
}

void CheckWhenConditions(const FlatSystem& flat) {
  for (const FlatWhen& w : flat.whens) {
    if (IsTruth(flat, w.condition)) continue;
    throw ModelError(w.loc, "the when-condition '" + flat.WhenText(w) +
                                "' is a Real expression, not a truth value; write a relation (x > 0), a Boolean or initial()");
  }
}

void CheckBuildTimeValues(const FlatSystem& flat) {
  const ExprPool& pool = *flat.pool;
  const char* const kFinite = ": a value known at build time must be a finite number";
  CheckEquations(flat, flat.equations);
  CheckEquations(flat, flat.initial_equations);
  // When-clauses: the condition, the assignments and the reinits.
  for (const FlatWhen& w : flat.whens) {
    auto check = [&](ExprId e, const std::string& what) {
      if (e.valid() && pool.IsSingular(e)) {
        throw ModelError(w.loc, Describe(flat, e) + ", in " + what + " of when-clause '" + flat.WhenText(w) + "'" + kFinite);
      }
    };
    check(w.condition, "the condition");
    for (const auto& [v, value] : w.assigns) check(value, "the value of " + flat.VariableName(v));
    for (const auto& [v, value] : w.reinits) check(value, "reinit(" + flat.VariableName(v) + ", ...)");
  }
  for (const FlatImpact& impact : flat.impacts) {
    for (ExprId e : {impact.gap, impact.velocity, impact.restitution, impact.v_small, impact.release}) {
      if (e.valid() && pool.IsSingular(e)) throw ModelError(impact.loc, Describe(flat, e) + ", in an impact" + kFinite);
    }
  }
  for (const FlatOutput& o : flat.outputs) {
    if (pool.IsSingular(o.expr)) throw ModelError(o.loc, Describe(flat, o.expr) + ", in output '" + o.text + "'" + kFinite);
  }
}

}  // namespace momenta
