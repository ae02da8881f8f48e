// Parameters computed at the start become variables (core/flatten/free_parameters.h).

#include "core/flatten/free_parameters.h"

#include <string>
#include <vector>

#include "core/base/error.h"
#include "core/expr/expr_substitution.h"

namespace momenta::flatten_internal {

namespace {

/// The variable that stands for parameter `id` from now on, with its equation: der(v) = 0 for a
/// free parameter, v = binding (read through `subst`) for one computed from free ones.
VarId AddParameterVariable(FlatSystem* flat, ParamId id, bool free, Substitution* subst) {
  ExprPool& pool = *flat->pool;
  const FlatParameter& p = flat->parameters[id.value()];
  const std::string name = flat->ParameterName(id);
  if (p.evaluate) {
    throw ModelError(p.loc, name + " is evaluated when the model is built (evaluate: true), so it cannot be " +
                                (free ? "computed at the start (fixed: false)" : "computed from a parameter with fixed: false"));
  }
  FlatVariable v;
  v.name = flat->Own(name);
  v.start = pool.Param(id);  // the guess: the parameter's value (start:, or -p)
  v.instance = p.instance;
  v.loc = p.loc;
  v.type = p.type;
  const VarId var(static_cast<uint32_t>(flat->variables.size()));
  flat->variables.push_back(v);
  FlatEquation eq;
  eq.loc = p.loc;
  eq.instance = p.instance;
  eq.origin = p.instance.valid() ? EquationOrigin::kComponent : EquationOrigin::kModel;
  if (free) {
    eq.residual = pool.Der(var);
    eq.text = flat->Own("der(" + name + ") = 0 (" + name + " has fixed: false: computed at the start, then constant)");
  } else {
    eq.residual = pool.Sub(pool.Var(var), subst->Apply(p.binding));
    eq.text = flat->Own(name + " = its binding (computed from a parameter with fixed: false)");
  }
  flat->equations.push_back(eq);
  return var;
}

}  // namespace

void MakeFreeParametersVariables(FlattenContext* context) {
  if (context->free_parameters.empty()) return;
  FlatSystem& flat = context->flat;
  ExprPool& pool = context->pool();
  std::vector<bool> free(flat.parameters.size(), false);
  for (ParamId id : context->free_parameters) free[id.value()] = true;
  Substitution subst(&pool);
  // In binding order, so that a dependent's binding already reads the variables it depends on.
  for (ParamId id : flat.parameter_order) {
    const bool is_free = free[id.value()];
    if (!is_free && !subst.Touches(flat.parameters[id.value()].binding)) continue;
    const VarId var = AddParameterVariable(&flat, id, is_free, &subst);
    subst.Set(pool.Param(id), pool.Var(var));
  }
  auto apply = [&](ExprId* e) {
    if (e->valid()) *e = subst.Apply(*e);
  };
  for (FlatEquation& eq : flat.equations) apply(&eq.residual);
  for (FlatEquation& eq : flat.initial_equations) apply(&eq.residual);
  for (FlatWhen& w : flat.whens) {
    apply(&w.condition);
    for (auto& assign : w.assigns) apply(&assign.second);
    for (auto& reinit : w.reinits) apply(&reinit.second);
  }
  for (FlatImpact& impact : flat.impacts) {
    for (ExprId* e : {&impact.gap, &impact.velocity, &impact.restitution, &impact.v_small, &impact.release}) apply(e);
  }
  for (FlatOutput& o : flat.outputs) apply(&o.expr);
}

}  // namespace momenta::flatten_internal
