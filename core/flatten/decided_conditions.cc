// Conditional connectors decided when the instances are made (core/flatten/decided_conditions.h).

#include "core/flatten/decided_conditions.h"

#include <algorithm>
#include <cmath>
#include <set>

namespace momenta::flatten_internal {

namespace {

/// Whether a `-p` override names a parameter called `name` of some instance ("R[3].useHeatPort").
bool Overridden(const ParameterOverrides& overrides, const std::string& name) {
  for (const auto& entry : overrides) {
    const std::string& key = entry.first;
    if (key.size() > name.size() && key[key.size() - name.size() - 1] == '.' &&
        key.compare(key.size() - name.size(), name.size(), name) == 0) {
      return true;
    }
  }
  return false;
}

/// The number of variables of a connector slot.
uint32_t SlotVariables(const ConnectorSlot& cs) {
  return cs.type->is_signal ? 1 : static_cast<uint32_t>(cs.type->potentials.size() + cs.type->flows.size());
}

/// Whether `t` names a variable of a connector decided absent.
bool NamesAbsent(const TypeLayout& layout, const std::vector<int8_t>& connector, const Template& t) {
  for (size_t k = 0; k < connector.size(); ++k) {
    const ConnectorSlot& cs = layout.connectors[k];
    if (connector[k] == 0 && NamesLocalVariables(t, cs.first_local_var, SlotVariables(cs))) return true;
  }
  return false;
}

/// Whether `e`, a template's copy with local variable j as variable j, names a variable of a
/// connector decided absent.
bool NamesAbsent(const TypeLayout& layout, const std::vector<int8_t>& connector, const ExprPool& pool, ExprId e) {
  if (!(pool.mask(e) & (kHasVar | kHasDer | kHasPre))) return false;
  for (ExprId leaf : CollectLeaves(pool, e, kHasVar | kHasDer | kHasPre)) {
    const uint32_t local = pool.node(leaf).a;
    for (size_t k = 0; k < connector.size(); ++k) {
      const ConnectorSlot& cs = layout.connectors[k];
      if (connector[k] == 0 && local >= cs.first_local_var && local < cs.first_local_var + SlotVariables(cs)) {
        return true;
      }
    }
  }
  return false;
}

/// Leaves to the passes every decided connector whose condition `t` reads or whose variables it
/// names.
void LeaveToThePasses(const TypeLayout& layout, const Template& t, DecidedConditions* d) {
  for (size_t k = 0; k < d->connector.size(); ++k) {
    if (d->connector[k] < 0) continue;
    const ConnectorSlot& cs = layout.connectors[k];
    const uint32_t q = layout.param_index.at(cs.decl->condition);
    const bool reads = std::any_of(t.nodes.begin(), t.nodes.end(),
                                   [&](const TNode& n) { return n.kind == TNode::kLocalParam && n.local == q; });
    if (reads || NamesLocalVariables(t, cs.first_local_var, SlotVariables(cs))) d->connector[k] = -1;
  }
}

/// The equations' copies for the connectors decided in `d.connector`, as the passes would leave
/// them: false, with some connectors left to the passes, when an equation reads a condition
/// outside an if-condition that it decides (`b and x`, `b*x`: the passes fold whole conditions
/// of parameters only), or names an absent connector while an if-expression is left (the passes
/// might fold it away and keep the equation). Whether an equation names the absent connector, or
/// is 0 = 0, is read from its copy in a pool of its own, which folds as the model's pool folds
/// (`0*heatPort.T` names nothing).
bool FixEquations(const TypeLayout& layout, DecidedConditions* d) {
  std::vector<double> values(layout.params.size(), std::nan(""));
  for (size_t k = 0; k < d->connector.size(); ++k) {
    if (d->connector[k] >= 0) values[layout.param_index.at(layout.connectors[k].decl->condition)] = d->connector[k];
  }
  // The folded conditions, each made once in the pool: distinct conditions are distinct nodes
  // there, as in the model's pool.
  ExprPool pool;
  std::set<uint32_t> conditions;
  std::vector<ExprId> made;
  bool kept = true;
  auto fix = [&](const std::vector<Template>& templates, const std::vector<PartInfo>& info, bool initial,
                 std::vector<DecidedConditions::Use>* use, std::vector<Template>* fixed) {
    use->assign(templates.size(), DecidedConditions::kAsLayout);
    fixed->assign(templates.size(), Template());
    for (size_t j = 0; j < templates.size(); ++j) {
      const Template& t = templates[j];
      const bool reads = ReadsFixedParameter(t, values);
      if (!reads && !NamesAbsent(layout, d->connector, t)) continue;
      std::vector<int32_t> folded;
      bool outside = false;
      // A table's copy needs the instance's tables, which the pool below has not.
      Template f = reads && !ReadsTable(t) ? FixLocalParameters(t, values, &folded, &outside) : t;
      if (outside || ReadsTable(t)) {
        LeaveToThePasses(layout, t, d);
        kept = false;
        continue;
      }
      if (!folded.empty()) {
        CopyTemplate(&pool, t, VarId(0), ParamId(0), &made, NoTable, /*cached_constants=*/false);
        for (int32_t c : folded) conditions.insert(made[c].value());
      }
      const ExprId copy = CopyTemplate(&pool, f, VarId(0), ParamId(0), &made, NoTable, /*cached_constants=*/false);
      if (NamesAbsent(layout, d->connector, pool, copy)) {
        if (pool.HasIf(copy)) {
          LeaveToThePasses(layout, f, d);
          kept = false;
        }
        (*use)[j] = DecidedConditions::kLeftOut;
        continue;
      }
      if (!reads) continue;  // named in the template only: the pool folds it away
      // An equation of a conditional block whose guard is false is no equation, nor is an
      // initial equation that folds to 0 = 0 (FoldStructuralConditions).
      if (pool.IsConst(copy, 0.0) && (initial || info[j].guarded)) {
        (*use)[j] = DecidedConditions::kLeftOut;
        continue;
      }
      (*use)[j] = DecidedConditions::kFixed;
      (*fixed)[j] = std::move(f);
    }
  };
  fix(layout.equations, layout.equation_info, false, &d->equation_use, &d->equations);
  fix(layout.initial_equations, layout.initial_info, true, &d->initial_use, &d->initial_equations);
  d->conditions = static_cast<uint32_t>(conditions.size());
  return kept;
}

}  // namespace

std::vector<int8_t> DecidableConnectors(const TypeLayout& layout, const std::vector<const Modifier*>& param_modifiers,
                                        const ParameterOverrides& overrides) {
  std::vector<int8_t> connector(layout.connectors.size(), -1);
  // A conditional part's equations and connections are resolved by the passes, with the rest.
  if (std::any_of(layout.subs.begin(), layout.subs.end(), [](const SubInstance& s) { return s.condition.root >= 0; })) {
    return connector;
  }
  for (size_t k = 0; k < layout.connectors.size(); ++k) {
    const std::string& condition = layout.connectors[k].decl->condition;
    if (condition.empty()) continue;
    auto at = layout.param_index.find(condition);
    if (at == layout.param_index.end()) continue;
    const uint32_t q = at->second;
    const LocalParam& lp = layout.params[q];
    const Template& binding = layout.param_defaults[q];
    // An outer parameter (`world.X`) is bound to the model's inner component after the
    // instances are made: not a number of the type's.
    if (lp.sub >= 0 || lp.name.find('.') != std::string::npos || lp.decl->type != ValueType::kBoolean ||
        param_modifiers[q] != nullptr ||
        binding.nodes.size() != 1 || binding.nodes[0].kind != TNode::kConst || Overridden(overrides, lp.name)) {
      continue;
    }
    connector[k] = binding.nodes[0].value != 0 ? 1 : 0;
  }
  return connector;
}

DecidedConditions DecideConditions(const TypeLayout& layout, std::vector<int8_t> decidable) {
  DecidedConditions d;
  d.connector = std::move(decidable);
  // A connection inside the type that names the connector: the passes decide what stays of it;
  // so they do for an impact that names it (its contact law is made outside the templates).
  for (size_t k = 0; k < d.connector.size(); ++k) {
    if (d.connector[k] < 0) continue;
    const ConnectorSlot& cs = layout.connectors[k];
    const uint32_t first = cs.first_local_var, count = SlotVariables(cs);
    auto names = [&](const Template& t) { return NamesLocalVariables(t, first, count); };
    auto is_slot_variable = [&](uint32_t local) { return local >= first && local < first + count; };
    for (const TypeLayout::ImpactTemplate& im : layout.impacts) {
      if (is_slot_variable(im.force) || is_slot_variable(im.contact) || names(im.gap) || names(im.velocity) ||
          names(im.restitution) || names(im.v_small) || names(im.release)) {
        d.connector[k] = -1;
      }
    }
    auto connects = [&](const std::vector<Template>& templates, const std::vector<PartInfo>& info) {
      for (size_t j = 0; j < templates.size(); ++j) {
        const EquationOrigin o = info[j].origin;
        if (o != EquationOrigin::kComponent && o != EquationOrigin::kInitial && names(templates[j])) return true;
      }
      return false;
    };
    if (connects(layout.equations, layout.equation_info) || connects(layout.initial_equations, layout.initial_info)) {
      d.connector[k] = -1;
    }
  }
  while (d.Any() && !FixEquations(layout, &d)) {
  }
  return d;
}

}  // namespace momenta::flatten_internal
