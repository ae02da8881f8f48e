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

bool ReadsFixed(const Template& t, const std::vector<double>& values) {
  return std::any_of(t.nodes.begin(), t.nodes.end(), [&](const TNode& n) {
    return n.kind == TNode::kLocalParam && n.local < values.size() && !std::isnan(values[n.local]);
  });
}

/// Whether `t` names a variable of a connector decided absent.
bool NamesAbsent(const TypeLayout& layout, const std::vector<int8_t>& connector, const Template& t) {
  for (size_t k = 0; k < connector.size(); ++k) {
    const ConnectorSlot& cs = layout.connectors[k];
    if (connector[k] == 0 && NamesLocalVariables(t, cs.first_local_var, SlotVariables(cs))) return true;
  }
  return false;
}

/// The equations' copies for the connectors decided in `d.connector`: false, with those
/// connectors left to the passes, when an equation that names an absent one still holds an
/// if-expression after folding (the passes might fold it away and keep the equation).
bool FixEquations(const TypeLayout& layout, DecidedConditions* d) {
  std::vector<double> values(layout.params.size(), std::nan(""));
  for (size_t k = 0; k < d->connector.size(); ++k) {
    if (d->connector[k] >= 0) values[layout.param_index.at(layout.connectors[k].decl->condition)] = d->connector[k];
  }
  // The folded conditions, each made once in a pool of its own: distinct conditions are
  // distinct nodes there, as in the model's pool.
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
      std::vector<int32_t> folded;
      const bool reads = ReadsFixed(t, values);
      Template f = reads ? FixLocalParameters(t, values, &folded) : Template();
      const Template& now = reads ? f : t;
      if (NamesAbsent(layout, d->connector, now)) {
        if (HasIfExpression(now)) {
          // Left to the passes: every connector this equation names.
          for (size_t k = 0; k < d->connector.size(); ++k) {
            const ConnectorSlot& cs = layout.connectors[k];
            if (d->connector[k] == 0 && NamesLocalVariables(now, cs.first_local_var, SlotVariables(cs))) {
              d->connector[k] = -1;
            }
          }
          kept = false;
        }
        (*use)[j] = DecidedConditions::kLeftOut;
        continue;
      }
      if (!reads) continue;
      if (!folded.empty()) {
        CopyTemplate(&pool, t, VarId(0), ParamId(0), &made, NoTable, /*cached_constants=*/false);
        for (int32_t c : folded) conditions.insert(made[c].value());
      }
      // An equation of a conditional block whose guard is false is no equation, nor is an
      // initial equation that folds to 0 = 0 (FoldStructuralConditions).
      const bool zero = f.nodes.size() == 1 && f.nodes[0].kind == TNode::kConst && f.nodes[0].value == 0;
      if (zero && (initial || info[j].guarded)) {
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
    if (lp.sub >= 0 || lp.decl->type != ValueType::kBoolean || param_modifiers[q] != nullptr ||
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
  // A connection inside the type that names the connector: the passes decide what stays of it.
  for (size_t k = 0; k < d.connector.size(); ++k) {
    if (d.connector[k] < 0) continue;
    const ConnectorSlot& cs = layout.connectors[k];
    for (const auto* list : {&layout.equations, &layout.initial_equations}) {
      const auto& info = list == &layout.equations ? layout.equation_info : layout.initial_info;
      for (size_t j = 0; j < list->size(); ++j) {
        const EquationOrigin o = info[j].origin;
        if (o != EquationOrigin::kComponent && o != EquationOrigin::kInitial &&
            NamesLocalVariables((*list)[j], cs.first_local_var, SlotVariables(cs))) {
          d.connector[k] = -1;
        }
      }
    }
  }
  while (d.Any() && !FixEquations(layout, &d)) {
  }
  return d;
}

}  // namespace momenta::flatten_internal
