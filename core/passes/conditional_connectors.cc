#include "core/passes/conditional_connectors.h"

#include "core/expr/expr_algebra.h"

namespace momenta {

namespace {

/// The first variable of `absent` that `e` names (its value, derivative or left limit), if any.
VarId NamedAbsent(const ExprPool& p, ExprId e, const std::vector<bool>& absent) {
  if (!(p.mask(e) & (kHasVar | kHasDer | kHasPre))) return VarId();
  thread_local std::vector<ExprId> leaves;  // one buffer for every equation
  CollectLeaves(p, e, kHasVar | kHasDer | kHasPre, &leaves);
  for (ExprId leaf : leaves) {
    const Node& n = p.node(leaf);
    if ((n.op == Op::kVar || n.op == Op::kDer || n.op == Op::kPre) && absent[n.a]) return VarId(n.a);
  }
  return VarId();
}

}  // namespace

size_t ResolveConditionalConnectors(EquationSystem* sys, const std::vector<double>& params) {
  if (sys->flat->conditional_connectors.empty()) return 0;
  // MutableFlat replaces sys->flat only by a copy while another holder keeps this one alive.
  const FlatSystem& flat = *sys->flat;
  ExprPool& p = *sys->pool;
  // Which connectors are absent; connecting one is the user's error.
  std::vector<bool> absent(flat.variables.size(), false);
  std::vector<const FlatConditionalConnector*> gone;
  std::vector<uint32_t> by_var(flat.variables.size(), 0);  // absent variable -> its connector in `gone`
  for (const FlatConditionalConnector& cc : flat.conditional_connectors) {
    if (params[cc.condition.value()] != 0) continue;
    if (cc.connected_at.known()) {
      // The names are made for the message only (one per absent connector otherwise).
      const FlatInstance& inst = flat.instances[cc.instance.value()];
      const std::string cond = flat.ParameterName(cc.condition);
      const std::string path = flat.InstancePath(cc.instance);
      throw ModelError(cc.connected_at, "cannot connect " + path + "." + cc.name + ": " + path + " (" +
                                            inst.type->name + ") has the connector " + cc.name + " only when " +
                                            cond.substr(path.size() + 1) + " is true, and " + cond +
                                            " is false; set " + cond.substr(path.size() + 1) + ": true in " +
                                            path + "'s entry");
    }
    for (uint32_t k = 0; k < cc.num_potentials + cc.num_flows; ++k) {
      absent[cc.first_var.value() + k] = true;
      by_var[cc.first_var.value() + k] = static_cast<uint32_t>(gone.size());
    }
    gone.push_back(&cc);
  }
  FlatSystem& f = sys->MutableFlat();
  for (const FlatConditionalConnector& cc : flat.conditional_connectors) {
    f.structural[flat.ParameterName(cc.condition)] = params[cc.condition.value()];
  }
  if (gone.empty()) return 0;
  auto absent_text = [&](VarId v) {
    const FlatConditionalConnector& cc = *gone[by_var[v.value()]];
    const std::string path = flat.InstancePath(cc.instance);
    return flat.VariableName(v) + ", but " + path + " has no connector " + cc.name + " (" +
           flat.ParameterName(cc.condition) + " is false)";
  };

  // Equations: the component's own that name the connector hold only with it; a model equation
  // that names it is an error.
  auto keep = [&](const SystemEquation& eq) {
    // A deferred equation (invalid) is of a type without conditional connectors.
    VarId v = eq.residual.valid() ? NamedAbsent(p, eq.residual, absent) : VarId();
    if (!v.valid()) return true;
    if (eq.kind == SystemEquation::Kind::kFixedStart) return false;
    const FlatEquation& fe = eq.kind == SystemEquation::Kind::kDynamic ? f.equations[eq.origin]
                                                                       : f.initial_equations[eq.origin];
    if (fe.origin == EquationOrigin::kComponent || fe.origin == EquationOrigin::kInitial) {
      if (fe.instance.valid()) return false;
    }
    if (fe.origin == EquationOrigin::kUnconnectedFlow) return false;  // 0 = 0 once the flow is zero
    throw ModelError(fe.loc, "the equation '" + f.EquationText(fe) + "' names " + absent_text(v));
  };
  for (auto* list : {&sys->equations, &sys->initial}) {
    std::vector<SystemEquation> kept;
    for (const SystemEquation& eq : *list) {
      if (keep(eq)) kept.push_back(eq);
    }
    list->swap(kept);
  }
  for (size_t k = 0; k < sys->outputs.size(); ++k) {
    VarId v = NamedAbsent(p, sys->outputs[k], absent);
    if (v.valid()) throw ModelError(f.outputs[k].loc, "the output '" + f.outputs[k].text + "' names " + absent_text(v));
  }

  // Absent, the connector's variables are constants: zero (its flows, being unconnected, are).
  for (uint32_t v = 0; v < absent.size(); ++v) {
    if (!absent[v]) continue;
    sys->eliminated->Set(p.Var(VarId(v)), p.Zero());
    if (ExprId der = p.FindLeaf(Op::kDer, v); der.valid()) sys->eliminated->Set(der, p.Zero());
    if (ExprId pre = p.FindLeaf(Op::kPre, v); pre.valid()) sys->eliminated->Set(pre, p.Zero());
    sys->role[v] = VarRole::kConstant;
  }
  // The equations, initial equations and outputs left name none of these variables (those that
  // did are gone, or were an error above): only the event parts can still hold them.
  sys->ApplySubstitutionToEvents(sys->eliminated.get());
  return gone.size();
}

}  // namespace momenta
