#include "core/passes/index_reduction.h"

#include <algorithm>
#include <tuple>
#include <unordered_map>

namespace momenta {

namespace {

/// How many equations hold each derivative leaf: by variable for first derivatives (nearly all of
/// them; a flat array), in a map for higher ones.
class DerivativeUses {
 public:
  DerivativeUses(const ExprPool& pool, size_t num_variables) : pool_(pool), first_(num_variables, 0) {}
  uint32_t& operator[](ExprId der) {
    const Node& n = pool_.node(der);
    return n.b == 0 ? first_[n.a] : higher_[der.value()];
  }

 private:
  const ExprPool& pool_;
  std::vector<uint32_t> first_;                    ///< der(x), by x
  std::unordered_map<uint32_t, uint32_t> higher_;  ///< by node id
};

/// Step 1: der(s) -> expression of v, from a defining equation v = c*der(s) + offset. With
/// `to_states`, only where v is differentiated itself (a state: known to the causal order).
/// `leaves` holds the equations' leaves, and is kept current.
void DerivativeAliases(EquationSystem* sys, IndexStats* stats, EquationLeaves* leaves, bool to_states = false) {
  ExprPool& p = *sys->pool;
  const std::vector<bool> diff = to_states ? leaves->Differentiated(p, sys->role.size()) : std::vector<bool>();
  // How many equations hold each der(s), and the one der(s) of each equation that holds exactly
  // one (invalid otherwise).
  DerivativeUses uses(p, sys->role.size());
  std::vector<ExprId> only_der(sys->equations.size());
  for (size_t k = 0; k < sys->equations.size(); ++k) {
    if (!(p.mask(sys->equations[k].residual) & kHasDer)) continue;
    size_t found = 0;
    for (const ExprId* l = leaves->begin(k); l != leaves->end(k); ++l) {
      if (p.op(*l) != Op::kDer) continue;
      ++uses[*l];
      only_der[k] = found++ == 0 ? *l : ExprId();
    }
  }
  Substitution rewrite(&p);
  std::vector<bool> defining(sys->equations.size(), false);
  AffineForm form;
  for (size_t k = 0; k < sys->equations.size(); ++k) {
    if (!only_der[k].valid() || uses[only_der[k]] < 2) continue;
    ExprId der = only_der[k];
    if (rewrite.Has(der)) continue;
    ExprId r = sys->equations[k].residual;
    if (p.mask(r) & (kHasPre | kHasTime | kHasInitial)) continue;
    if (!DecomposeAffine(&p, r, 2, &form) || form.terms.size() != 2) continue;
    // One term is der(s), the other a variable.
    auto [t_der, t_var] = p.op(form.terms[0].first) == Op::kDer ? std::pair{form.terms[0], form.terms[1]}
                                                                 : std::pair{form.terms[1], form.terms[0]};
    if (p.op(t_der.first) != Op::kDer || p.op(t_var.first) != Op::kVar) continue;
    if (to_states && !diff[p.node(t_var.first).a]) continue;
    // c_d*der(s) + c_v*v + off = 0  =>  der(s) = -(c_v*v + off)/c_d
    ExprId value = p.Neg(p.Div(p.Add(p.Mul(p.Const(t_var.second), t_var.first), form.offset),
                               p.Const(t_der.second)));
    rewrite.Set(der, value);
    defining[k] = true;
    ++stats->derivative_aliases;
  }
  if (rewrite.size() == 0) return;
  for (size_t k = 0; k < sys->equations.size(); ++k) {
    if (defining[k]) continue;
    if (!leaves->Touches(rewrite, k)) continue;
    ExprId& r = sys->equations[k].residual;
    r = rewrite.Apply(r);
    leaves->Update(p, k, r);
  }
  for (auto& e : sys->initial) e.residual = rewrite.Apply(e.residual);
  for (auto& o : sys->outputs) o = rewrite.Apply(o);
}

/// stateSelect priorities (FlatVariable::state_priority).

/// Whether every variable leaf among `leaves` (an equation's) has `members` set.
bool AllVariablesIn(const ExprPool& p, const ExprId* begin, const ExprId* end, const std::vector<bool>& members) {
  for (const ExprId* l = begin; l != end; ++l) {
    const Node& n = p.node(*l);
    if (n.op == Op::kVar && !members[n.a]) return false;
  }
  return true;
}

/// Step 2: constraints among differentiated variables. `leaves` holds the equations' leaves, and
/// is kept current.
void ConstrainedStates(EquationSystem* sys, IndexStats* stats, EquationLeaves* leaves) {
  ExprPool& p = *sys->pool;
  const FlatSystem& flat = *sys->flat;
  Substitution& s = *sys->eliminated;
  std::vector<bool> diff = leaves->Differentiated(p, sys->role.size());
  // Equations that define a variable as the derivative of another, u = c*der(x) + offset (a
  // body's v = der(r)), by x (the first such equation): a constrained x with such a u can stay
  // an unknown.
  constexpr int32_t kNone = -1;
  std::vector<int32_t> derivative_definition(sys->role.size(), kNone);
  {
    AffineForm form;
    for (uint32_t k = 0; k < sys->equations.size(); ++k) {
      ExprId r = sys->equations[k].residual;
      const uint8_t m = p.mask(r);
      if (!(m & kHasDer) || (m & (kHasPre | kHasTime | kHasInitial))) continue;
      if (!DecomposeAffine(&p, r, 2, &form) || form.terms.size() != 2) continue;
      const auto& [t0, t1] = std::pair{form.terms[0], form.terms[1]};
      const bool d0 = p.op(t0.first) == Op::kDer && p.DerOrder(t0.first) == 1 && p.op(t1.first) == Op::kVar;
      const bool d1 = p.op(t1.first) == Op::kDer && p.DerOrder(t1.first) == 1 && p.op(t0.first) == Op::kVar;
      if (d0 == d1) continue;
      int32_t& definition = derivative_definition[p.node((d0 ? t0 : t1).first).a];
      if (definition == kNone) definition = static_cast<int32_t>(k);
      // A velocity that should be a state (MSL's v_rel = der(s_rel) with stateSelect prefer)
      // takes part in constraints among states as if it were differentiated: a constraint
      // v_b = v_a + v_rel then eliminates the mass's v_b (default) and der(v_b) becomes
      // der(v_a) + der(v_rel), so v_rel is a state, as Dymola chooses. Without this, v_rel
      // stays algebraic and a reinit of v_a (a hard stop) would make v_rel jump where MSL's
      // reference keeps it.
      const uint32_t u = p.node((d0 ? t1 : t0).first).a;
      if (flat.variables[u].state_priority >= kStatePrefer) diff[u] = true;
    }
  }
  // How many constraints each state occurs in. Eliminating a variable that occurs in one
  // constraint keeps every substitution local; eliminating one shared by two (a mass between two
  // spring-dampers) would make each mass position a sum over the chain: dense expressions.
  std::vector<uint32_t> constraint_count(sys->role.size(), 0);
  std::vector<ExprId> vars, original_vars;  // scratch for the loops below
  // Which equations are constraints among states as they stand now: one that is not and is not
  // rewritten below is skipped there without collecting its variables again.
  std::vector<bool> maybe_constraint(sys->equations.size(), false);
  for (size_t k = 0; k < sys->equations.size(); ++k) {
    const ExprId r = sys->equations[k].residual;
    const uint8_t m = p.mask(r);
    if ((m & (kHasDer | kHasPre | kHasInitial)) || !(m & kHasVar)) continue;
    // Without derivatives and pre-values, the equation's leaves are its variables.
    if (!AllVariablesIn(p, leaves->begin(k), leaves->end(k), diff)) continue;
    maybe_constraint[k] = true;
    for (const ExprId* v = leaves->begin(k); v != leaves->end(k); ++v) ++constraint_count[p.node(*v).a];
  }
  std::vector<bool> drop(sys->equations.size(), false);
  // Variables replaced by the solution of a constraint they share with another: a second such
  // solution that holds one (the next frame of a chain) is nested, and is kept instead (below).
  std::vector<bool> shared_solution(sys->role.size(), false);
  bool changed = false;
  for (size_t k = 0; k < sys->equations.size(); ++k) {
    SystemEquation& eq = sys->equations[k];
    const ExprId original = eq.residual;
    // Rewritten by what this pass replaced so far (only if it holds some of it: the same result).
    ExprId r = changed && leaves->Touches(s, k) ? s.Apply(eq.residual) : eq.residual;
    eq.residual = r;
    if (r != original) leaves->Update(p, k, r);
    if (r == original && !maybe_constraint[k]) continue;
    const uint8_t m = p.mask(r);
    if ((m & (kHasDer | kHasPre | kHasInitial)) || !(m & kHasVar)) continue;
    if (!AllVariablesIn(p, leaves->begin(k), leaves->end(k), diff)) continue;
    vars.assign(leaves->begin(k), leaves->end(k));
    // Eliminate a `stateSelect: never` variable first, then the variable in the fewest
    // constraints, then the one that least wants to be a state (avoid < default < prefer), then
    // the one declared last. An `always` variable is never eliminated here, nor anything while a
    // `never` one cannot be: such constraints go to Pantelides and the dummy derivatives, which
    // honour the priorities whether or not the constraint is linear.
    auto rank = [&](uint32_t v) {
      const int prio = flat.variables[v].state_priority;
      return std::make_tuple(prio == kStateNever ? 0 : prio == kStateAlways ? 2 : 1, constraint_count[v], prio, -static_cast<int64_t>(v));
    };
    std::sort(vars.begin(), vars.end(), [&](ExprId a, ExprId b) { return rank(p.node(a).a) < rank(p.node(b).a); });
    for (ExprId x : vars) {
      const int prio = flat.variables[p.node(x).a].state_priority;
      if (prio == kStateAlways) break;
      ExprId coefficient;
      ExprId value = SolveFor(&p, r, x, true, &coefficient);
      ExprId dvalue = value.valid() ? TimeDerivative(&p, value) : ExprId();
      if (!dvalue.valid()) {
        if (prio == kStateNever) break;
        continue;
      }
      uint32_t v = p.node(x).a;
      ExprId der = p.Der(VarId(v));
      if (!p.IsConst(coefficient)) sys->guards.push_back({coefficient, eq.origin, VarId(v)});
      const int32_t def = derivative_definition[v];
      auto nests = [&] {
        CollectLeaves(p, original, kHasVar, &original_vars);
        for (ExprId w : original_vars) {
          if (shared_solution[p.node(w).a]) return true;
        }
        return false;
      };
      if (constraint_count[v] >= 2 && def != kNone && nests()) {
        // x is shared with another constraint (a frame between two bars of a chain), and its
        // constraint holds a variable already replaced so: replacing x too would nest every such
        // solution into the next one, so that the position of the k-th link of a chain becomes a
        // sum of k terms, and its velocity and acceleration (and their Jacobians) grow with it.
        // x stays an unknown with the constraint as its equation instead (the chain restarts
        // from it), its derivative becomes the variable u that the definition
        // u = c*der(x) + offset names, and that definition becomes the differentiated constraint
        // (der(x) replaced by the time derivative of the solution). Every equation stays local.
        // u is left to the next round: its new equation is a constraint on velocities.
        SystemEquation& definition = sys->equations[def];
        ExprId u_eq = s.Apply(definition.residual);
        ExprId der_value;  // der(x) from the definition: c*der(x) + c_u*u + offset = 0
        ExprId unused;
        der_value = SolveFor(&p, u_eq, der, false, &unused);
        if (der_value.valid() && !(p.mask(der_value) & kHasDer)) {
          definition.residual = ReplaceLeaf(&p, u_eq, der, dvalue);
          leaves->Update(p, def, definition.residual);
          maybe_constraint[def] = true;  // a new residual: looked at afresh
          s.Set(der, der_value);
          derivative_definition[v] = kNone;
          ++stats->kept_constraints;
          changed = true;
          break;
        }
      }
      s.Set(x, value);
      s.Set(der, dvalue);
      ExprId pre = p.FindLeaf(Op::kPre, v);
      if (pre.valid()) s.Set(pre, value);  // pre() of a continuous variable is its value
      sys->role[v] = VarRole::kConstrained;
      shared_solution[v] = constraint_count[v] >= 2;
      ++stats->constrained_states;
      drop[k] = true;
      changed = true;
      break;
    }
  }
  std::vector<SystemEquation> kept;
  kept.reserve(sys->equations.size());
  for (size_t k = 0; k < sys->equations.size(); ++k) {
    if (!drop[k]) kept.push_back(sys->equations[k]);
  }
  sys->equations.swap(kept);
  leaves->Drop(drop);
  if (changed) ApplyEliminations(sys, leaves);
}

}  // namespace

size_t SubstituteDerivativeAliases(EquationSystem* sys) {
  IndexStats stats;
  EquationLeaves leaves;
  leaves.Collect(*sys);
  DerivativeAliases(sys, &stats, &leaves, /*to_states=*/true);
  return stats.derivative_aliases;
}

EquationSystem ReduceIndex(EquationSystem sys, IndexStats* stats, EquationLeaves* leaves) {
  EquationLeaves own;
  if (leaves == nullptr) leaves = &own;
  if (!leaves->valid()) leaves->Collect(sys);
  DerivativeAliases(&sys, stats, leaves);
  ConstrainedStates(&sys, stats, leaves);
  return sys;
}

}  // namespace momenta
