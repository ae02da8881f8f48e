// The stages of CompileModel for events (core/compile/compile_stages.h): event relations frozen
// into conditions with their zero-crossing functions, the discrete equations, the when-clauses
// and the impacts. What the simulator does with them is solver/'s (event iteration, impacts).

#include <algorithm>
#include <string>
#include <unordered_map>
#include <unordered_set>

#include "core/compile/compile_stages.h"
#include "core/expr/expr_leaves.h"

namespace momenta {

namespace {

/// Event relations: every relation outside noEvent() whose operands change with time or state
/// becomes a condition, frozen between events. A relation of discrete variables, pre-values and
/// parameters alone (`u <> pre(u)` of change(u), `k > 0` of an Integer) is not one: its operands
/// change only at events, so it is evaluated as it stands, and reads the values of the event
/// iteration's current round (Modelica's rule: such relations make no crossing functions).
class ConditionTable {
 public:
  ConditionTable(ExprPool* pool, const ExprNamer& names, const std::vector<int32_t>& disc_of_var)
      : pool_(pool), names_(names), disc_of_var_(disc_of_var) {}

  /// Registers the relations below `e` (outermost first, then nested ones).
  void Collect(ExprId e) {
    ExprPool& p = *pool_;
    if (!(p.mask(e) & kHasRelation)) return;
    std::vector<uint32_t> stack{e.value()};
    while (!stack.empty()) {
      uint32_t id = stack.back();
      stack.pop_back();
      const Node& n = p.node(ExprId(id));
      if (!(n.mask & kHasRelation) || !visited_.insert(id).second) continue;
      if (IsRelation(n.op) && !(n.flags & kNoEvent) && !p.IsParamOnly(ExprId(id)) && !OfDiscreteOnly(ExprId(id))) {
        relations_.push_back(ExprId(id));
      }
      int arity = Arity(n.op);
      if (arity >= 1) stack.push_back(n.a);
      if (arity >= 2) stack.push_back(n.b);
      if (arity >= 3) stack.push_back(n.c);
    }
  }

  /// Finishes: the map from relation nodes to condition leaves.
  void Freeze() {
    // In the relations' order: the condition leaves' nodes are made in the order of their numbers,
    // not in the order of a hash map's buckets.
    for (uint32_t r = 0; r < relations_.size(); ++r) map_.emplace(relations_[r].value(), pool_->Cond(r));
  }

  /// `e` with every registered relation replaced by its condition leaf.
  ExprId Replace(ExprId e) {
    if (map_.empty() || !(pool_->mask(e) & kHasRelation)) return e;
    return ReplaceNodes(pool_, e, map_, kHasRelation);
  }

  size_t size() const { return relations_.size(); }
  ExprId relation(size_t r) const { return relations_[r]; }

  /// Whether `e` reads no time, derivative or continuous unknown: only discrete variables,
  /// pre-values and parameters.
  bool OfDiscreteOnly(ExprId e) const {
    const ExprPool& p = *pool_;
    if (p.mask(e) & (kHasTime | kHasDer | kHasInitial | kHasCond)) return false;
    for (ExprId leaf : CollectLeaves(p, e, kHasVar)) {
      const Node& v = p.node(leaf);
      if (v.op != Op::kVar || disc_of_var_[v.a] < 0) return false;
    }
    return true;
  }
  std::string Text(size_t r) const { return ToString(*pool_, relations_[r], names_); }

 private:
  ExprPool* pool_;
  const ExprNamer& names_;
  const std::vector<int32_t>& disc_of_var_;  ///< flat variable -> discrete index, -1 if continuous
  std::unordered_map<uint32_t, ExprId> map_;
  std::unordered_set<uint32_t> visited_;
  std::vector<ExprId> relations_;
};

/// Calls `fn(e)` on every expression that is evaluated: the model's residuals, outputs, initial
/// and redundant equations, and the system's discrete equations, when-clauses and impacts.
template <class Fn>
void ForEachEvaluated(EquationSystem* sys, CompiledModel* m, Fn fn) {
  for (ExprId& e : m->residual_exprs) fn(e);
  for (ExprId& e : m->output_exprs) fn(e);
  for (ExprId& e : m->initial_exprs) fn(e);
  for (ExprId& e : m->redundant_exprs) fn(e);
  for (auto& d : sys->discrete) fn(d.value);
  for (auto& w : sys->whens) {
    fn(w.condition);
    for (auto& a : w.assigns) fn(a.second);
    for (auto& r : w.reinits) fn(r.second);
  }
  for (auto& im : sys->impacts) {
    for (ExprId* e : {&im.gap, &im.velocity, &im.release}) fn(*e);
  }
}

/// dz/dt of the crossing function `z`, or an invalid id when it reads der() (it would need second
/// derivatives).
ExprId CrossingRate(ExprPool* pool, const VariableSlots& slots, ExprId z) {
  ExprPool& p = *pool;
  ExprId rate = (p.mask(z) & kHasDer) ? ExprId() : TimeDerivative(&p, z);
  if (!rate.valid()) return rate;
  // Discrete variables are constant between events: their der() is 0, not an unknown's y'.
  std::unordered_map<uint32_t, ExprId> constant;
  for (ExprId leaf : CollectLeaves(p, rate, kHasDer)) {
    const Node der = p.node(leaf);
    if (der.op == Op::kDer && slots.y_of_var[der.a] < 0) constant[leaf.value()] = p.Zero();
  }
  if (!constant.empty()) rate = ReplaceNodes(&p, rate, constant, kHasDer);
  return rate;
}

/// By flat variable: whether der() of it appears in an equation of the flat system.
std::vector<bool> Differentiated(const FlatSystem& flat) {
  std::vector<bool> differentiated(flat.variables.size(), false);
  for (const FlatEquation& eq : flat.equations) {
    if (!eq.residual.valid() || !(flat.pool->mask(eq.residual) & kHasDer)) continue;
    for (ExprId leaf : CollectLeaves(*flat.pool, eq.residual, kHasDer)) {
      if (flat.pool->op(leaf) == Op::kDer) differentiated[flat.pool->node(leaf).a] = true;
    }
  }
  return differentiated;
}

/// The value slot of `reinit(target, value)` in a when-clause (`text`): the y index of the state
/// that `target` is, or that replaced it as an alias (x = c*u + o gives u := (value - o)/c), and
/// the value for that state. Throws ModelError when the target is not a state.
std::pair<uint32_t, ExprId> ReinitOfState(const EquationSystem& sys, const VariableSlots& slots,
                                          const CompiledModel& m, VarId target, ExprId value,
                                          const FlatWhen& when, const std::string& text,
                                          const std::vector<bool>& differentiated) {
  ExprPool& p = *sys.pool;
  const FlatSystem& flat = *sys.flat;
  ExprId rep = sys.eliminated->Apply(p.Var(target));
  AffineForm form;
  if (!DecomposeAffine(&p, rep, 1, &form) || form.terms.size() != 1 || p.op(form.terms[0].first) != Op::kVar) {
    throw ModelError(when.loc, "reinit(" + flat.VariableName(target) + ", …) in '" + text +
                                   "': the variable is not a state");
  }
  uint32_t u = p.node(form.terms[0].first).a;
  if (u != target.value() && !differentiated[target.value()]) {
    // An alias of a state (y = 2*x) is not one itself: Modelica reinit()s only what der() is of.
    throw ModelError(when.loc, "reinit(" + flat.VariableName(target) + ", …) in '" + text + "': " +
                                   flat.VariableName(target) + " is not a state (der() of it appears in no equation; it is computed from " +
                                   flat.VariableName(VarId(u)) + ")");
  }
  int32_t y = slots.y_of_var[u];
  if (y < 0 || !m.is_state[y]) {
    throw ModelError(when.loc, "reinit(" + flat.VariableName(target) + ", …) in '" + text +
                                   "': the variable is not a state (der() of it appears nowhere)");
  }
  return {static_cast<uint32_t>(y),
          p.Div(p.Sub(value, form.offset), p.Const(form.terms[0].second))};
}

}  // namespace

void CollectConditions(EquationSystem* sys, CompileContext* ctx, CompiledModel* m) {
  ExprPool& p = *sys->pool;
  const ExprNamer names = sys->flat->Namer();
  ConditionTable conds(&p, names, ctx->slots.disc_of_var);
  ForEachEvaluated(sys, m, [&](ExprId& e) { conds.Collect(e); });
  conds.Freeze();
  std::vector<bool> is_discrete(ctx->slots.disc_of_var.size());
  for (size_t v = 0; v < is_discrete.size(); ++v) is_discrete[v] = ctx->slots.disc_of_var[v] >= 0;
  for (size_t r = 0; r < conds.size(); ++r) {
    const Node rel = p.node(conds.relation(r));
    ExprId z = conds.Replace(p.Sub(ExprId(rel.a), ExprId(rel.b)));
    // A time event: time, parameters and discrete values alone (MSL's Pulse, `time >=
    // startTime + pre(count)*period`), which are constant between events, so the time at which
    // z reaches zero is known once an event has been handled.
    bool time_only = !(p.mask(z) & (kHasDer | kHasCond | kHasInitial)) &&
                     AllLeavesIn(p, z, kHasVar, is_discrete);
    ctx->zero_crossings.push_back(z);
    const ExprId rate = CrossingRate(&p, ctx->slots, z);
    ctx->zero_crossing_rates.push_back(rate.valid() ? rate : p.Zero());
    m->conditions.push_back({rel.op, time_only, conds.Text(r), rate.valid()});
  }
  ForEachEvaluated(sys, m, [&](ExprId& e) { e = conds.Replace(e); });
}

void CompileDiscrete(const EquationSystem& sys, const CompileContext& ctx,
                     ProgramCompiler* compiler, CompiledModel* m) {
  m->discrete_starts = compiler->Compile(ctx.discrete_start);
  // The equations store into their registers in order: disc_base + index (the layout's fixed
  // part, known now).
  std::vector<ExprId> values;
  std::vector<uint32_t> registers;
  for (const auto& d : sys.discrete) {
    values.push_back(d.value);
    m->discrete_equations.emplace_back(d.var, d.value);
    registers.push_back(compiler->layout().disc_base +
                        static_cast<uint32_t>(ctx.slots.disc_of_var[d.var.value()]));
  }
  m->discrete_update = compiler->Compile(values, &registers);
}

void CompileZeroCrossings(const CompileContext& ctx, ProgramCompiler* compiler, CompiledModel* m) {
  m->zero_crossings = compiler->Compile(ctx.zero_crossings);
  m->zero_crossing_rates = compiler->Compile(ctx.zero_crossing_rates);
}

void CompileWhens(const EquationSystem& sys, const CompileContext& ctx, ProgramCompiler* compiler,
                  CompiledModel* m) {
  const FlatSystem& flat = *sys.flat;
  // Per clause its condition; its statements' values in one list, which the slots index.
  std::vector<ExprId> cond_values, statement_values;
  std::vector<bool> differentiated;  // made at the first reinit
  for (const auto& w : sys.whens) {
    const FlatWhen& when = flat.whens[w.origin];
    CompiledModel::When cw;
    cw.text = flat.WhenText(when);
    cond_values.push_back(w.condition);
    for (const auto& [target, value] : w.assigns) {
      int32_t d = ctx.slots.disc_of_var[target.value()];
      if (d < 0) {
        throw ModelError(when.loc, "when '" + cw.text + "' assigns " + flat.VariableName(target) +
                                       ", which is not a discrete variable");
      }
      cw.assigns.emplace_back(static_cast<uint32_t>(d), static_cast<uint32_t>(statement_values.size()));
      statement_values.push_back(value);
    }
    for (const auto& [target, value] : w.reinits) {
      if (differentiated.empty()) differentiated = Differentiated(flat);
      const auto [y, state_value] = ReinitOfState(sys, ctx.slots, *m, target, value, when, cw.text, differentiated);
      cw.reinits.emplace_back(y, static_cast<uint32_t>(statement_values.size()));
      statement_values.push_back(state_value);
    }
    m->whens.push_back(std::move(cw));
  }
  sys.eliminated->ReleaseMemo();  // grown again by the reinits' targets
  m->when_conditions = compiler->Compile(cond_values);
  m->when_values = compiler->Compile(statement_values);
}

void CompileImpacts(const EquationSystem& sys, const CompileContext& ctx, ProgramCompiler* compiler,
                    CompiledModel* m) {
  const FlatSystem& flat = *sys.flat;
  const ExprPool& p = *sys.pool;
  // The contact-mode row that carries Newton's law at an impact, and the values the simulator
  // watches (gap, velocity, restitution, v_small, release).
  std::vector<ExprId> values;
  for (const auto& im : sys.impacts) {
    const FlatImpact& fi = flat.impacts[im.origin];
    CompiledModel::Impact ci;
    ci.name = flat.InstancePath(fi.instance);
    auto row = std::find(ctx.residual_source.begin(), ctx.residual_source.end(), fi.mode_equation);
    if (row == ctx.residual_source.end()) {
      throw ModelError(fi.loc, "the impact of " + ci.name + " lost its contact equation during simplification (an internal limitation; please report the model)");
    }
    ci.mode_row = static_cast<uint32_t>(row - ctx.residual_source.begin());
    ci.contact = static_cast<uint32_t>(ctx.slots.disc_of_var[im.contact.value()]);
    for (ExprId e : {im.gap, im.velocity}) {
      for (ExprId leaf : CollectLeaves(p, e, kHasVar | kHasDer)) {
        const Node leaf_node = p.node(leaf);  // kVar and kDer: a is the variable
        const int32_t y = ctx.slots.y_of_var[leaf_node.a];
        if (leaf_node.op == Op::kDer || (y >= 0 && !m->is_state[y])) m->impacts_read_algebraic = true;
      }
    }
    for (ExprId e : {im.gap, im.velocity, im.restitution, im.v_small, im.release}) values.push_back(e);
    m->impacts.push_back(std::move(ci));
  }
  m->impact_values = compiler->Compile(values);
}

}  // namespace momenta
