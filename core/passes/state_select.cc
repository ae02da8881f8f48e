#include "core/passes/state_select.h"

#include "core/expr/expr_algebra.h"

namespace momenta {

namespace {


/// Whether `v` is a state, or an alias (±u + offset) of one.
bool IsStateOrAlias(const EquationSystem& sys, const Structure& structure, uint32_t v) {
  if (sys.role[v] == VarRole::kUnknown) return structure.is_state[v];
  if (sys.role[v] != VarRole::kAlias) return false;
  ExprPool& p = *sys.pool;
  AffineForm form;
  if (!DecomposeAffine(&p, sys.eliminated->Apply(p.Var(VarId(v))), 1, &form) || form.terms.size() != 1 ||
      p.op(form.terms[0].first) != Op::kVar) {
    return false;
  }
  uint32_t u = p.node(form.terms[0].first).a;
  return sys.role[u] == VarRole::kUnknown && structure.is_state[u];
}

}  // namespace

void CheckStateSelect(const EquationSystem& sys, const Structure& structure,
                      std::vector<std::string>* warnings) {
  const FlatSystem& flat = *sys.flat;
  for (uint32_t v = 0; v < sys.role.size(); ++v) {
    const FlatVariable& fv = flat.variables[v];
    if (fv.state_priority == kStateAlways && !IsStateOrAlias(sys, structure, v)) {
      const std::string name = flat.VariableName(VarId(v));
      std::string why;
      switch (sys.role[v]) {
        case VarRole::kConstant: why = "it is a constant (an equation fixes it to a parameter expression)"; break;
        case VarRole::kConstrained: why = "a constraint determines it from other states"; break;
        case VarRole::kAlias: why = "it is an alias of a variable that is not a state"; break;
        default: why = "der(" + name + ") appears in no equation (states are chosen among the variables that appear differentiated)";
      }
      throw ModelError(fv.loc, "stateSelect: always on " + name + " cannot be honoured: " + why +
                                   ". Use stateSelect: prefer (or default) on " + name + ".");
    }
    if (fv.state_priority == kStateNever && sys.role[v] == VarRole::kUnknown &&
        structure.is_state[v]) {
      warnings->push_back(fv.loc.ToString() + ": stateSelect: never on " + flat.VariableName(VarId(v)) +
                          ", but it is a state: no other variable can carry its degree of freedom");
    }
  }
}

}  // namespace momenta
