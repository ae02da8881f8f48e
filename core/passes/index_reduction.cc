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

/// Whether every variable leaf among `leaves` (an equation's) has `members` set.
bool AllVariablesIn(const ExprPool& p, const ExprId* begin, const ExprId* end, const std::vector<bool>& members) {
  for (const ExprId* l = begin; l != end; ++l) {
    const Node& n = p.node(*l);
    if (n.op == Op::kVar && !members[n.a]) return false;
  }
  return true;
}

/// Step 2: constraints among differentiated variables, each solved for one of its variables x,
/// which leaves with der(x). `leaves` holds the equations' leaves, and is kept current.
class ConstrainedStates {
 public:
  ConstrainedStates(EquationSystem* sys, IndexStats* stats, EquationLeaves* leaves)
      : sys_(*sys),
        pool_(*sys->pool),
        flat_(*sys->flat),
        eliminated_(*sys->eliminated),
        stats_(*stats),
        leaves_(*leaves),
        differentiated_(leaves->Differentiated(pool_, sys->role.size())),
        derivative_definition_(sys->role.size(), kNone),
        constraint_count_(sys->role.size(), 0),
        maybe_constraint_(sys->equations.size(), false),
        drop_(sys->equations.size(), false),
        shared_solution_(sys->role.size(), false) {}

  void Run() {
    FindDerivativeDefinitions();
    CountConstraints();
    for (size_t k = 0; k < sys_.equations.size(); ++k) SolveConstraint(k);
    std::vector<SystemEquation> kept;
    kept.reserve(sys_.equations.size());
    for (size_t k = 0; k < sys_.equations.size(); ++k) {
      if (!drop_[k]) kept.push_back(sys_.equations[k]);
    }
    sys_.equations.swap(kept);
    leaves_.Drop(drop_);
    if (changed_) ApplyEliminations(&sys_, &leaves_);
  }

 private:
  static constexpr int32_t kNone = -1;

  /// Equations that define a variable as the derivative of another, u = c*der(x) + offset (a
  /// body's v = der(r)), by x (the first such equation): a constrained x with such a u can stay
  /// an unknown.
  void FindDerivativeDefinitions() {
    ExprPool& p = pool_;
    AffineForm form;
    for (uint32_t k = 0; k < sys_.equations.size(); ++k) {
      ExprId r = sys_.equations[k].residual;
      const uint8_t m = p.mask(r);
      if (!(m & kHasDer) || (m & (kHasPre | kHasTime | kHasInitial))) continue;
      if (!DecomposeAffine(&p, r, 2, &form) || form.terms.size() != 2) continue;
      const auto& [t0, t1] = std::pair{form.terms[0], form.terms[1]};
      const bool d0 = p.op(t0.first) == Op::kDer && p.DerOrder(t0.first) == 1 && p.op(t1.first) == Op::kVar;
      const bool d1 = p.op(t1.first) == Op::kDer && p.DerOrder(t1.first) == 1 && p.op(t0.first) == Op::kVar;
      if (d0 == d1) continue;
      int32_t& definition = derivative_definition_[p.node((d0 ? t0 : t1).first).a];
      if (definition == kNone) definition = static_cast<int32_t>(k);
      // A velocity that should be a state (MSL's v_rel = der(s_rel) with stateSelect prefer)
      // takes part in constraints among states as if it were differentiated: a constraint
      // v_b = v_a + v_rel then eliminates the mass's v_b (default) and der(v_b) becomes
      // der(v_a) + der(v_rel), so v_rel is a state, as Dymola chooses. Without this, v_rel
      // stays algebraic and a reinit of v_a (a hard stop) would make v_rel jump where MSL's
      // reference keeps it.
      const uint32_t u = p.node((d0 ? t1 : t0).first).a;
      if (flat_.variables[u].state_priority >= kStatePrefer) differentiated_[u] = true;
    }
  }

  /// Whether `r`, an equation's residual with leaves `leaves_` of row k, is a constraint among
  /// states: no derivatives, pre-values or initial(), and every variable differentiated.
  bool IsConstraint(ExprId r, size_t k) const {
    const uint8_t m = pool_.mask(r);
    if ((m & (kHasDer | kHasPre | kHasInitial)) || !(m & kHasVar)) return false;
    // Without derivatives and pre-values, the equation's leaves are its variables.
    return AllVariablesIn(pool_, leaves_.begin(k), leaves_.end(k), differentiated_);
  }

  /// How many constraints each state occurs in. Eliminating a variable that occurs in one
  /// constraint keeps every substitution local; eliminating one shared by two (a mass between two
  /// spring-dampers) would make each mass position a sum over the chain: dense expressions. Also
  /// which equations are constraints as they stand now: one that is not and is not rewritten is
  /// skipped later without collecting its variables again.
  void CountConstraints() {
    for (size_t k = 0; k < sys_.equations.size(); ++k) {
      if (!IsConstraint(sys_.equations[k].residual, k)) continue;
      maybe_constraint_[k] = true;
      for (const ExprId* v = leaves_.begin(k); v != leaves_.end(k); ++v) {
        ++constraint_count_[pool_.node(*v).a];
      }
    }
  }

  /// Equation k, rewritten by what this pass replaced so far, solved for one of its variables
  /// when it is a constraint among states.
  void SolveConstraint(size_t k) {
    ExprPool& p = pool_;
    SystemEquation& eq = sys_.equations[k];
    const ExprId original = eq.residual;
    // Rewritten by what this pass replaced so far (only if it holds some of it: the same result).
    ExprId r =
        changed_ && leaves_.Touches(eliminated_, k) ? eliminated_.Apply(eq.residual) : eq.residual;
    eq.residual = r;
    if (r != original) leaves_.Update(p, k, r);
    if (r == original && !maybe_constraint_[k]) return;
    if (!IsConstraint(r, k)) return;
    vars_.assign(leaves_.begin(k), leaves_.end(k));
    // Eliminate a `stateSelect: never` variable first, then the variable in the fewest
    // constraints, then the one that least wants to be a state (avoid < default < prefer), then
    // the one declared last. An `always` variable is never eliminated here, nor anything while a
    // `never` one cannot be: such constraints go to Pantelides and the dummy derivatives, which
    // honour the priorities whether or not the constraint is linear.
    auto rank = [&](uint32_t v) {
      const int prio = flat_.variables[v].state_priority;
      const int kind = prio == kStateNever ? 0 : prio == kStateAlways ? 2 : 1;
      return std::make_tuple(kind, constraint_count_[v], prio, -static_cast<int64_t>(v));
    };
    std::sort(vars_.begin(), vars_.end(),
              [&](ExprId a, ExprId b) { return rank(p.node(a).a) < rank(p.node(b).a); });
    for (ExprId x : vars_) {
      const int prio = flat_.variables[p.node(x).a].state_priority;
      if (prio == kStateAlways) break;
      ExprId coefficient;
      ExprId value = SolveFor(&p, r, x, true, &coefficient);
      ExprId dvalue = value.valid() ? TimeDerivative(&p, value) : ExprId();
      if (!dvalue.valid()) {
        if (prio == kStateNever) break;
        continue;
      }
      const uint32_t v = p.node(x).a;
      ExprId der = p.Der(VarId(v));
      if (!p.IsConst(coefficient)) sys_.guards.push_back({coefficient, eq.origin, VarId(v)});
      if (constraint_count_[v] >= 2 && derivative_definition_[v] != kNone && Nests(original) &&
          KeepConstraint(v, der, dvalue)) {
        return;
      }
      Eliminate(k, x, value, der, dvalue);
      return;
    }
  }

  /// Whether the constraint `original` holds a variable replaced by the solution of a constraint
  /// it shares with another.
  bool Nests(ExprId original) {
    CollectLeaves(pool_, original, kHasVar, &original_vars_);
    for (ExprId w : original_vars_) {
      if (shared_solution_[pool_.node(w).a]) return true;
    }
    return false;
  }

  /// x (variable v) is shared with another constraint (a frame between two bars of a chain), and
  /// its constraint holds a variable already replaced so: replacing x too would nest every such
  /// solution into the next one, so that the position of the k-th link of a chain becomes a sum
  /// of k terms, and its velocity and acceleration (and their Jacobians) grow with it. x stays an
  /// unknown with the constraint as its equation instead (the chain restarts from it), its
  /// derivative becomes the variable u that the definition u = c*der(x) + offset names, and that
  /// definition becomes the differentiated constraint (der(x) replaced by `dvalue`, the time
  /// derivative of the solution). Every equation stays local. u is left to the next round: its
  /// new equation is a constraint on velocities. Returns false when der(x) cannot be taken from
  /// the definition.
  bool KeepConstraint(uint32_t v, ExprId der, ExprId dvalue) {
    ExprPool& p = pool_;
    const int32_t def = derivative_definition_[v];
    SystemEquation& definition = sys_.equations[def];
    ExprId u_eq = eliminated_.Apply(definition.residual);
    ExprId unused;
    // der(x) from the definition: c*der(x) + c_u*u + offset = 0
    ExprId der_value = SolveFor(&p, u_eq, der, false, &unused);
    if (!der_value.valid() || (p.mask(der_value) & kHasDer)) return false;
    definition.residual = ReplaceLeaf(&p, u_eq, der, dvalue);
    leaves_.Update(p, def, definition.residual);
    maybe_constraint_[def] = true;  // a new residual: looked at afresh
    eliminated_.Set(der, der_value);
    derivative_definition_[v] = kNone;
    ++stats_.kept_constraints;
    changed_ = true;
    return true;
  }

  /// x and der(x) replaced everywhere by the solution of constraint k and its time derivative.
  void Eliminate(size_t k, ExprId x, ExprId value, ExprId der, ExprId dvalue) {
    ExprPool& p = pool_;
    const uint32_t v = p.node(x).a;
    eliminated_.Set(x, value);
    eliminated_.Set(der, dvalue);
    ExprId pre = p.FindLeaf(Op::kPre, v);
    if (pre.valid()) eliminated_.Set(pre, value);  // pre() of a continuous variable is its value
    sys_.role[v] = VarRole::kConstrained;
    shared_solution_[v] = constraint_count_[v] >= 2;
    ++stats_.constrained_states;
    drop_[k] = true;
    changed_ = true;
  }

  EquationSystem& sys_;
  ExprPool& pool_;
  const FlatSystem& flat_;
  Substitution& eliminated_;
  IndexStats& stats_;
  EquationLeaves& leaves_;
  /// By variable: a state, or a velocity that prefers to be one.
  std::vector<bool> differentiated_;
  /// By variable x: the equation u = c*der(x) + offset that defines its derivative, or kNone.
  std::vector<int32_t> derivative_definition_;
  std::vector<uint32_t> constraint_count_;  ///< by variable: the constraints it occurs in
  /// By equation: a constraint as it stood at the start.
  std::vector<bool> maybe_constraint_;
  std::vector<bool> drop_;  ///< by equation: solved, leaves
  /// Variables replaced by the solution of a constraint they share with another: a second such
  /// solution that holds one (the next frame of a chain) is nested, and is kept instead.
  std::vector<bool> shared_solution_;
  bool changed_ = false;
  std::vector<ExprId> vars_, original_vars_;  // scratch
};

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
  ConstrainedStates(&sys, stats, leaves).Run();
  return sys;
}

}  // namespace momenta
