#include "core/passes/conditional_connectors.h"

#include <algorithm>
#include <map>
#include <string>
#include <unordered_map>
#include <unordered_set>

#include "core/base/error.h"
#include "core/expr/expr_algebra.h"
#include "core/expr/expr_eval.h"
#include "core/expr/expr_substitution.h"

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

/// Whether fixed start `eq` (v - start) names an absent variable: its own, as a start is an
/// expression of parameters (read without collecting the leaves of 500 000 of them).
bool NamesAbsentFixedStart(const ExprPool& p, const SystemEquation& eq, const std::vector<bool>& absent) {
  if (!eq.residual.valid()) return false;
  const Node& n = p.node(eq.residual);
  if (n.op == Op::kSub && p.node(ExprId(n.a)).op == Op::kVar && p.node(ExprId(n.a)).a == eq.origin &&
      !(p.mask(ExprId(n.b)) & (kHasVar | kHasDer | kHasPre))) {
    return absent[eq.origin];
  }
  return NamedAbsent(p, eq.residual, absent).valid();
}

/// The parameters `e` reads, through the parameters' bindings. Called once per conditional part:
/// the parameters seen are a set of the few reached, not a flag per parameter of the model (an
/// array of conditional parts would make that quadratic, as it made structural_conditions.cc).
std::vector<uint32_t> ParametersRead(const FlatSystem& flat, ExprId e) {
  const ExprPool& p = *flat.pool;
  std::vector<ExprId> todo = CollectLeaves(p, e, kHasParam);
  std::unordered_set<uint32_t> seen;
  std::vector<uint32_t> read;
  while (!todo.empty()) {
    const uint32_t q = p.node(todo.back()).a;
    todo.pop_back();
    if (!seen.insert(q).second) continue;
    read.push_back(q);
    const ExprId binding = flat.parameters[q].binding;
    if (binding.valid() && (p.mask(binding) & kHasParam)) {
      for (ExprId leaf : CollectLeaves(p, binding, kHasParam)) todo.push_back(leaf);
    }
  }
  return read;
}

/// What is absent, and why: the variables of absent connectors and parts, and the instances of
/// absent parts (their own parts included).
struct Absent {
  std::vector<bool> vars, instances;
  /// By absent variable: its connector (< connectors.size()) or, after them, its part.
  std::vector<uint32_t> why;
  std::vector<const FlatConditionalConnector*> connectors;
  std::vector<const FlatConditionalPart*> parts;
  bool OfPart(VarId v) const { return why[v.value()] >= connectors.size(); }
};

/// The absent conditional connectors; connecting one is the user's error.
void FindAbsentConnectors(const FlatSystem& flat, const std::vector<double>& params, Absent* absent) {
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
      absent->vars[cc.first_var.value() + k] = true;
      absent->why[cc.first_var.value() + k] = static_cast<uint32_t>(absent->connectors.size());
    }
    absent->connectors.push_back(&cc);
  }
}

/// The absent conditional parts (after the connectors: `why` counts past them). Their conditions'
/// parameters, Real ones too, are fixed when the model is built.
void FindAbsentParts(const FlatSystem& flat, const std::vector<double>& params, Absent* absent,
                     std::vector<uint32_t>* structural) {
  LeafValues values;
  values.params = params.data();
  for (const FlatConditionalPart& cp : flat.conditional_parts) {
    for (uint32_t q : ParametersRead(flat, cp.condition)) structural->push_back(q);
    if (Evaluate(*flat.pool, cp.condition, values) != 0) continue;
    const auto why = static_cast<uint32_t>(absent->connectors.size() + absent->parts.size());
    for (uint32_t k = 0; k < cp.num_vars; ++k) {
      // A part inside an absent part: the outer one says why.
      if (absent->vars[cp.first_var.value() + k]) continue;
      absent->vars[cp.first_var.value() + k] = true;
      absent->why[cp.first_var.value() + k] = why;
    }
    for (uint32_t k = 0; k < cp.num_instances; ++k) absent->instances[cp.instance.value() + k] = true;
    absent->parts.push_back(&cp);
  }
}

/// Whether connection equation `eq` inside a composite, which names `v` of the absent variables,
/// stays: a flow sum without the absent flows (they are zero), unless nothing is left; an
/// equality `member = reference` goes with an absent member. An absent reference would leave a
/// member that exists undetermined: the user's error (`absent_text` says why it is absent).
template <class AbsentText>
bool KeepConnection(ExprPool* pool, const FlatSystem& flat, const std::vector<bool>& absent, VarId v,
                    const FlatEquation& fe, SystemEquation* eq, const AbsentText& absent_text) {
  ExprPool& p = *pool;
  if (flat.variables[v.value()].is_flow) {
    std::unordered_map<uint32_t, ExprId> zero;
    for (ExprId leaf : CollectLeaves(p, eq->residual, kHasVar)) {
      if (absent[p.node(leaf).a]) zero.emplace(leaf.value(), p.Zero());
    }
    eq->residual = ReplaceNodes(&p, eq->residual, zero, kHasVar);
    return !p.IsConst(eq->residual, 0.0);
  }
  const Node& n = p.node(eq->residual);
  MOMENTA_CHECK_MSG(n.op == Op::kSub && p.node(ExprId(n.a)).op == Op::kVar,
                    "a connection's equality is member - reference");
  const VarId member(p.node(ExprId(n.a)).a);
  if (absent[member.value()]) return false;
  throw ModelError(fe.loc, "the connection '" + flat.EquationText(fe) + "' joins " + flat.VariableName(member) +
                               " to " + absent_text(v) + "; " + flat.VariableName(member) +
                               " exists without it and would be left undetermined: give its part the same " +
                               "condition, or connect it to something that is always there");
}

/// Absent, the variables are constants: zero (the flows, being unconnected, are). The equations,
/// initial equations and outputs left name none of them (those that did are gone, or were an
/// error): only the event parts can still hold them.
void ZeroAbsentVariables(EquationSystem* sys, const std::vector<bool>& absent) {
  ExprPool& p = *sys->pool;
  for (uint32_t v = 0; v < absent.size(); ++v) {
    if (!absent[v]) continue;
    sys->eliminated->Set(p.Var(VarId(v)), p.Zero());
    if (ExprId der = p.FindLeaf(Op::kDer, v); der.valid()) sys->eliminated->Set(der, p.Zero());
    if (ExprId pre = p.FindLeaf(Op::kPre, v); pre.valid()) sys->eliminated->Set(pre, p.Zero());
    sys->role[v] = VarRole::kConstant;
  }
  sys->ApplySubstitutionToEvents(sys->eliminated.get());
}

}  // namespace

size_t ResolveConditionalConnectors(EquationSystem* sys, const std::vector<double>& params, size_t* absent_parts) {
  if (absent_parts != nullptr) *absent_parts = 0;
  if (sys->flat->conditional_connectors.empty() && sys->flat->conditional_parts.empty()) return 0;
  // MutableFlat replaces sys->flat only by a copy while another holder keeps this one alive.
  const FlatSystem& flat = *sys->flat;
  ExprPool& p = *sys->pool;
  Absent absent;
  absent.vars.assign(flat.variables.size(), false);
  absent.why.assign(flat.variables.size(), 0);
  absent.instances.assign(flat.instances.size(), false);
  FindAbsentConnectors(flat, params, &absent);
  std::vector<uint32_t> structural;
  FindAbsentParts(flat, params, &absent, &structural);
  FlatSystem& f = sys->MutableFlat();
  for (const FlatConditionalConnector& cc : flat.conditional_connectors) {
    f.structural.Set(cc.condition, params[cc.condition.value()]);
  }
  for (uint32_t q : structural) f.structural.Set(ParamId(q), params[q]);
  if (absent_parts != nullptr) *absent_parts = absent.parts.size();
  if (absent.connectors.empty() && absent.parts.empty()) return 0;
  auto absent_text = [&](VarId v) {
    const uint32_t why = absent.why[v.value()];
    if (!absent.OfPart(v)) {
      const FlatConditionalConnector& cc = *absent.connectors[why];
      const std::string path = flat.InstancePath(cc.instance);
      return flat.VariableName(v) + ", but " + path + " has no connector " + cc.name + " (" +
             flat.ParameterName(cc.condition) + " is false)";
    }
    const FlatConditionalPart& cp = *absent.parts[why - absent.connectors.size()];
    return flat.VariableName(v) + ", but " + flat.InstancePath(cp.owner) + " has no part " +
           flat.InstancePath(cp.instance).substr(flat.InstancePath(cp.owner).size() + 1) + " (its condition " +
           cp.condition_text + " is false)";
  };

  // Every absent connector decided when its instance was made (the MSL's heat ports left off):
  // the instances' equations that named them were not made, and a connection to one is refused
  // above (a connection inside a type leaves its connectors to this pass), so only the model's
  // own equations and the fixed starts can name them.
  const bool all_decided = absent.parts.empty() &&
                           std::all_of(absent.connectors.begin(), absent.connectors.end(),
                                       [](const FlatConditionalConnector* cc) { return cc->decided == 0; });
  // Equations: an absent part's own go; the component's own that name an absent connector hold
  // only with it; a connection to an absent part or connector vanishes; anything else that names
  // them is an error.
  auto keep = [&](SystemEquation* eq) {
    if (eq->kind == SystemEquation::Kind::kFixedStart) return !NamesAbsentFixedStart(p, *eq, absent.vars);
    const FlatEquation& fe = eq->kind == SystemEquation::Kind::kDynamic ? f.equations[eq->origin]
                                                                        : f.initial_equations[eq->origin];
    if (all_decided && (fe.instance.valid() || fe.origin == EquationOrigin::kConnection)) return true;
    if (fe.instance.valid() && absent.instances[fe.instance.value()]) return false;
    // A deferred equation (invalid) names no conditional connector or part.
    const VarId v = eq->residual.valid() ? NamedAbsent(p, eq->residual, absent.vars) : VarId();
    if (!v.valid()) return true;
    if (fe.origin == EquationOrigin::kComponent || fe.origin == EquationOrigin::kInitial) {
      if (fe.instance.valid() && !absent.OfPart(v)) return false;
    }
    if (fe.origin == EquationOrigin::kUnconnectedFlow) return false;  // 0 = 0 once the flow is zero
    if (fe.origin == EquationOrigin::kConnection) return KeepConnection(&p, f, absent.vars, v, fe, eq, absent_text);
    throw ModelError(fe.loc, "the equation '" + f.EquationText(fe) + "' names " + absent_text(v));
  };
  for (auto* list : {&sys->equations, &sys->initial}) {
    std::vector<SystemEquation> kept;
    for (SystemEquation eq : *list) {
      if (keep(&eq)) kept.push_back(eq);
    }
    list->swap(kept);
  }
  for (size_t k = 0; k < sys->outputs.size(); ++k) {
    VarId v = NamedAbsent(p, sys->outputs[k], absent.vars);
    if (v.valid()) throw ModelError(f.outputs[k].loc, "the output '" + f.outputs[k].text + "' names " + absent_text(v));
  }
  // An absent part's when-clauses and impacts go with it.
  auto gone_with_part = [&](InstanceId i) { return i.valid() && absent.instances[i.value()]; };
  std::erase_if(sys->whens, [&](const SystemWhen& w) { return gone_with_part(f.whens[w.origin].instance); });
  std::erase_if(sys->impacts, [&](const SystemImpact& im) { return gone_with_part(f.impacts[im.origin].instance); });

  ZeroAbsentVariables(sys, absent.vars);
  return absent.connectors.size();
}

}  // namespace momenta
