// A variable is needed when an output uses it, or when a needed equation uses it; an equation is
// needed when it determines a needed variable (for a state x, the equation matched to der(x)).
// An initial equation is kept when it touches a needed variable, and then all its variables are
// needed too. The closure is a breadth-first walk over the matching.

#include "core/passes/pruning.h"

namespace momenta {

EquationSystem Prune(EquationSystem sys, Structure* st, PruneStats* stats) {
  const ExprPool& p = *sys.pool;
  const size_t nv = sys.role.size();
  std::vector<bool> need_var(nv, false), need_eq(sys.equations.size(), false),
      need_init(sys.initial.size(), false);
  std::vector<uint32_t> queue;
  auto mark = [&](uint32_t v) {
    // Cheapest test first: a variable is marked once per leaf that names it, and its flat record
    // is a cache miss each time.
    if (!need_var[v] && sys.role[v] == VarRole::kUnknown && !sys.flat->variables[v].discrete) {
      need_var[v] = true;
      queue.push_back(v);
    }
  };
  std::vector<ExprId> leaves;  // scratch
  auto mark_leaves = [&](ExprId e) {
    CollectLeaves(p, e, kHasVar | kHasDer | kHasPre, &leaves);
    for (ExprId leaf : leaves) mark(p.node(leaf).a);
  };
  // The variables of each initial equation, collected once for the repeated scans below: those
  // of initial equation k are init_vars[init_start[k] .. init_start[k+1]).
  std::vector<uint32_t> init_start{0}, init_vars;
  init_start.reserve(sys.initial.size() + 1);
  for (const SystemEquation& eq : sys.initial) {
    CollectLeaves(p, eq.residual, kHasVar | kHasDer | kHasPre, &leaves);
    for (ExprId leaf : leaves) init_vars.push_back(p.node(leaf).a);
    init_start.push_back(static_cast<uint32_t>(init_vars.size()));
  }
  for (ExprId o : sys.outputs) mark_leaves(o);
  // Event machinery is kept whole: what it reads and what it sets.
  for (const auto& w : sys.whens) {
    mark_leaves(w.condition);
    for (const auto& a : w.assigns) mark_leaves(a.second);
    for (const auto& r : w.reinits) {
      mark_leaves(r.second);
      mark_leaves(sys.pool->Var(r.first));
    }
  }
  for (const auto& im : sys.impacts) {
    for (ExprId e : {im.gap, im.velocity, im.release}) mark_leaves(e);
    mark_leaves(sys.pool->Var(im.force));
  }
  for (const auto& d : sys.discrete) mark_leaves(d.value);
  while (true) {
    while (!queue.empty()) {
      uint32_t v = queue.back();
      queue.pop_back();
      int32_t e = st->equation_of_var[v];
      if (e >= 0 && !need_eq[e]) {
        need_eq[e] = true;
        mark_leaves(sys.equations[e].residual);
      }
    }
    // Initial equations that touch what is kept.
    bool added = false;
    for (size_t k = 0; k < sys.initial.size(); ++k) {
      if (need_init[k]) continue;
      bool touches = false;
      for (uint32_t j = init_start[k]; j < init_start[k + 1] && !touches; ++j) {
        const uint32_t v = init_vars[j];
        // Discrete variables are always kept (events may need them), so are their initial values.
        touches = need_var[v] || (sys.role[v] == VarRole::kUnknown && sys.flat->variables[v].discrete);
      }
      if (touches) {
        need_init[k] = true;
        for (uint32_t j = init_start[k]; j < init_start[k + 1]; ++j) mark(init_vars[j]);
        added = true;
      }
    }
    if (!added && queue.empty()) break;
  }
  // Drop the rest and renumber the matching.
  std::vector<SystemEquation> eqs;
  std::vector<int32_t> var_of_eq;
  for (size_t k = 0; k < sys.equations.size(); ++k) {
    if (!need_eq[k]) {
      ++stats->equations;
      continue;
    }
    var_of_eq.push_back(st->var_of_equation[k]);
    eqs.push_back(sys.equations[k]);
  }
  sys.equations.swap(eqs);
  st->var_of_equation.swap(var_of_eq);
  std::fill(st->equation_of_var.begin(), st->equation_of_var.end(), -1);
  for (size_t k = 0; k < sys.equations.size(); ++k) {
    st->equation_of_var[st->var_of_equation[k]] = static_cast<int32_t>(k);
  }
  std::vector<SystemEquation> init;
  for (size_t k = 0; k < sys.initial.size(); ++k) {
    if (need_init[k]) {
      init.push_back(sys.initial[k]);
    } else {
      ++stats->initial_equations;
    }
  }
  sys.initial.swap(init);
  st->num_states = 0;
  for (uint32_t v = 0; v < nv; ++v) {
    if (sys.role[v] != VarRole::kUnknown || sys.flat->variables[v].discrete) continue;
    if (!need_var[v]) {
      sys.role[v] = VarRole::kPruned;
      st->is_state[v] = false;
      ++stats->variables;
    } else {
      st->num_states += st->is_state[v];
    }
  }
  return sys;
}

}  // namespace momenta
