#include "core/compile/compile.h"

#include <algorithm>
#include <sstream>
#include <unordered_map>
#include <unordered_set>

#include "core/base/graph.h"
#include "core/compile/initial_conditions.h"

namespace momenta {

namespace {

/// Where each flat variable lives at run time.
struct Slots {
  std::vector<int32_t> y_of_var;     ///< flat variable -> y index
  std::vector<int32_t> disc_of_var;  ///< flat variable -> discrete index
  std::vector<int32_t> state_of_y;   ///< y index -> state slot
};

struct Entry {
  int32_t row, col;
  ExprId value;
  /// A y' partial (cj dF/dy'): at the same (row, col) it comes after the y partial, so that the
  /// merged entry has the same form in every component (a loop body, core/compile/reroll.h).
  bool der = false;
};

bool ColumnMajor(const Entry& a, const Entry& b) {
  if (a.col != b.col) return a.col < b.col;
  if (a.row != b.row) return a.row < b.row;
  return a.der < b.der;
}

/// Start guesses for y. A start value that is not fixed is only a guess, and the components'
/// defaults (a body's position starts at 0) are poor ones where the fixed conditions determine the
/// variable: a pendulum chain's bodies would all start at the pivot while the joint angles put them
/// radians away. So the guesses are found as the initialisation system [F; G] would determine
/// them, in dependency (block-lower-triangular) order: an equation with one unknown not yet
/// guessed that is linear in it with a numeric coefficient gives its guess, from the guesses of
/// the others (first from the fixed start values and the parameters); when none is left, the
/// start values of the variables still open (algebraic loops) are taken and the search goes on.
/// Only equations of variables, parameters and constants are used; the guesses stay
/// parameter-only (each refers to the earlier ones' expressions, shared, so linear in size).
std::vector<ExprId> PropagatedStartGuesses(ExprPool* pool, const EquationSystem& sys, const CompiledModel& m, const Slots& slots) {
  ExprPool& p = *pool;
  const uint32_t n = static_cast<uint32_t>(m.unknowns.size());
  std::vector<ExprId> starts(n);
  std::vector<bool> known(n, false);
  for (uint32_t y = 0; y < n; ++y) {
    const uint32_t v = m.unknowns[y].value();
    starts[y] = sys.guess[v];
  }
  constexpr uint8_t kOther = kHasDer | kHasTime | kHasPre | kHasRelation | kHasInitial | kHasCond;
  // The rows and their unknowns (none is known yet), and each unknown's rows: two flat lists
  // with offsets, where a vector per row and per unknown made hundreds of thousands.
  std::vector<ExprId> rows;
  std::vector<uint32_t> row_start{0}, row_ys;
  std::vector<uint32_t> missing;
  std::vector<uint32_t> ready;
  std::vector<ExprId> leaves;  // scratch
  auto add_row = [&](ExprId e) {
    if (p.node(e).mask & kOther) return;
    CollectLeaves(p, e, kHasVar, &leaves);
    const size_t first = row_ys.size();
    for (ExprId leaf : leaves) {
      const int32_t y = slots.y_of_var[p.node(leaf).a];
      if (y < 0) {  // a discrete value: not known before the start values
        row_ys.resize(first);
        return;
      }
      row_ys.push_back(static_cast<uint32_t>(y));
    }
    const uint32_t r = static_cast<uint32_t>(rows.size());
    const uint32_t count = static_cast<uint32_t>(row_ys.size() - first);
    rows.push_back(e);
    row_start.push_back(static_cast<uint32_t>(row_ys.size()));
    missing.push_back(count);
    if (count == 1) ready.push_back(r);
  };
  for (ExprId e : m.residual_exprs) add_row(e);
  for (ExprId e : m.initial_exprs) add_row(e);
  std::vector<uint32_t> y_start(n + 1, 0), y_rows(row_ys.size());
  for (uint32_t y : row_ys) ++y_start[y + 1];
  for (uint32_t y = 0; y < n; ++y) y_start[y + 1] += y_start[y];
  {
    std::vector<uint32_t> next(y_start.begin(), y_start.end() - 1);
    for (uint32_t r = 0; r < rows.size(); ++r) {
      for (uint32_t k = row_start[r]; k < row_start[r + 1]; ++k) y_rows[next[row_ys[k]]++] = r;
    }
  }
  // Row r2 has one unknown fewer to find now that y is known.
  auto now_known = [&](uint32_t y) {
    known[y] = true;
    for (uint32_t k = y_start[y]; k < y_start[y + 1]; ++k) {
      const uint32_t r2 = y_rows[k];
      if (--missing[r2] == 1) ready.push_back(r2);
    }
  };
  std::unordered_map<uint32_t, ExprId> map;  // known unknowns -> their guesses, for one row
  for (size_t k = 0, next_open = 0;; ++k) {
    if (k == ready.size()) {
      // No explicit equation left: the first variable still open takes its start value.
      while (next_open < n && known[next_open]) ++next_open;
      if (next_open == n) break;
      now_known(static_cast<uint32_t>(next_open));
      --k;
      continue;
    }
    const uint32_t r = ready[k];
    if (missing[r] != 1) continue;
    uint32_t target = n;
    map.clear();
    for (uint32_t j = row_start[r]; j < row_start[r + 1]; ++j) {
      const uint32_t y = row_ys[j];
      if (!known[y]) {
        target = y;
      } else {
        map[p.Var(m.unknowns[y]).value()] = starts[y];
      }
    }
    if (target == n) continue;
    ExprId e = map.empty() ? rows[r] : ReplaceNodes(&p, rows[r], map, kHasVar);
    ExprId coefficient;
    ExprId value = SolveFor(&p, e, p.Var(m.unknowns[target]), false, &coefficient);
    if (!value.valid() || !p.IsParamOnly(value)) continue;
    starts[target] = value;
    now_known(target);
  }
  return starts;
}

/// Sorts `entries` (columns below `cols`) by ColumnMajor. They are made row by row, so a stable
/// counting sort by column orders them by (column, row) in linear time, and leaves only a y and
/// a y' partial of one (row, column) to put in order (std::sort, a call per comparison, was a
/// tenth of compilation on a large model). Entries in neither order are sorted the general way.
void SortColumnMajor(std::vector<Entry>* entries, int32_t cols) {
  std::vector<Entry>& in = *entries;
  auto column_major = [](const Entry& a, const Entry& b) { return ColumnMajor(a, b); };
  if (std::is_sorted(in.begin(), in.end(), column_major)) return;
  for (size_t k = 1; k < in.size(); ++k) {
    if (in[k].row < in[k - 1].row) {
      std::sort(in.begin(), in.end(), column_major);
      return;
    }
  }
  std::vector<uint32_t> next(static_cast<size_t>(cols) + 1, 0);  // per column: its next place
  for (const Entry& e : in) ++next[e.col + 1];
  for (int32_t c = 0; c < cols; ++c) next[c + 1] += next[c];
  std::vector<Entry> sorted(in.size());
  for (const Entry& e : in) sorted[next[e.col]++] = e;
  for (size_t k = 1; k < sorted.size(); ++k) {
    if (ColumnMajor(sorted[k], sorted[k - 1])) std::swap(sorted[k], sorted[k - 1]);
  }
  in.swap(sorted);
}

/// The pattern and values of `entries`, sorted by ColumnMajor.
void SortToPattern(std::vector<Entry>* entries, int32_t rows, int32_t cols, SparsePattern* pattern,
                   std::vector<ExprId>* values) {
  SortColumnMajor(entries, cols);
  pattern->rows = rows;
  pattern->cols = cols;
  pattern->col_start.assign(cols + 1, 0);
  pattern->row_index.clear();
  pattern->row_index.reserve(entries->size());
  values->clear();
  values->reserve(entries->size());
  for (const Entry& e : *entries) {
    ++pattern->col_start[e.col + 1];
    pattern->row_index.push_back(e.row);
    values->push_back(e.value);
  }
  for (int32_t c = 0; c < cols; ++c) pattern->col_start[c + 1] += pattern->col_start[c];
}

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
        index_.emplace(id, static_cast<uint32_t>(relations_.size()));
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
    for (const auto& [id, r] : index_) map_.emplace(id, pool_->Cond(r));
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
  std::unordered_map<uint32_t, uint32_t> index_;
  std::unordered_map<uint32_t, ExprId> map_;
  std::unordered_set<uint32_t> visited_;
  std::vector<ExprId> relations_;
};

}  // namespace

std::shared_ptr<CompiledModel> CompileModel(EquationSystem sys, const Structure& st,
                                            const std::vector<std::string>& output_names,
                                            BuildReport* report) {
  ExprPool& p = *sys.pool;
  const FlatSystem& flat = *sys.flat;
  const ExprNamer names = flat.Namer();
  // The eliminations are applied: their memo (8 bytes per pool node) is not needed here.
  sys.eliminated->ReleaseMemo();
  auto m = std::make_shared<CompiledModel>();
  m->flat = sys.flat;
  m->pool = sys.pool;
  m->experiment = flat.experiment;

  // Unknowns in declaration order, each with its matched equation; discrete variables apart.
  Slots slots;
  slots.y_of_var.assign(sys.role.size(), -1);
  slots.disc_of_var.assign(sys.role.size(), -1);
  std::vector<uint32_t> residual_source;
  for (uint32_t v = 0; v < sys.role.size(); ++v) {
    if (sys.role[v] != VarRole::kUnknown) continue;
    if (flat.variables[v].discrete) {
      slots.disc_of_var[v] = static_cast<int32_t>(m->discrete_vars.size());
      m->discrete_vars.push_back(VarId(v));
      continue;
    }
    slots.y_of_var[v] = static_cast<int32_t>(m->unknowns.size());
    m->unknowns.push_back(VarId(v));
    m->is_state.push_back(st.is_state[v]);
    m->nominal.push_back(flat.variables[v].nominal);
    const SystemEquation& eq = sys.equations[st.equation_of_var[v]];
    m->residual_exprs.push_back(eq.residual);
    m->residual_equations.push_back(eq);
    residual_source.push_back(eq.origin);
    if (st.is_state[v]) report->states.push_back(flat.VariableName(VarId(v)));
  }
  const uint32_t n = static_cast<uint32_t>(m->unknowns.size());
  const uint32_t nd = static_cast<uint32_t>(m->discrete_vars.size());
  slots.state_of_y.assign(n, -1);
  for (uint32_t y = 0; y < n; ++y) {
    if (!m->is_state[y]) continue;
    slots.state_of_y[y] = static_cast<int32_t>(m->state_y.size());
    m->state_y.push_back(y);
  }
  m->output_names = output_names;
  m->output_exprs = sys.outputs;

  // Discrete start values; initial equations `pre(d) = expr` set them instead.
  std::vector<ExprId> discrete_start(nd);
  for (uint32_t k = 0; k < nd; ++k) discrete_start[k] = sys.guess[m->discrete_vars[k].value()];
  std::vector<ExprId> pres, vars;  // scratch
  for (const auto& e : sys.initial) {
    CollectLeaves(p, e.residual, kHasPre, &pres);
    CollectLeaves(p, e.residual, kHasVar | kHasDer, &vars);
    if (pres.size() == 1 && vars.empty() && slots.disc_of_var[p.node(pres[0]).a] >= 0) {
      ExprId value = SolveFor(&p, e.residual, pres[0], true, nullptr);
      if (value.valid() && p.IsParamOnly(value)) {
        discrete_start[slots.disc_of_var[p.node(pres[0]).a]] = value;
        continue;
      }
    }
    m->initial_exprs.push_back(e.residual);
    m->initial_origin.push_back(sys.Describe(e));
  }
  m->guards = sys.guards;
  for (const auto& g : sys.guards) m->guard_text.push_back(ToString(p, g.divisor, names));

  // Redundant initial conditions are left out (and checked at the solution); states without an
  // initial condition take their start value (as Modelica tools do).
  InitialConditionPlan plan = PlanInitialConditions(sys, *m, slots.y_of_var, slots.state_of_y);
  for (size_t k = plan.redundant.size(); k-- > 0;) {
    const uint32_t g = plan.redundant[k];
    m->redundant_exprs.insert(m->redundant_exprs.begin(), m->initial_exprs[g]);
    m->redundant_origin.insert(m->redundant_origin.begin(), m->initial_origin[g]);
    m->redundant_from.insert(m->redundant_from.begin(), plan.redundant_from[k]);
    m->initial_exprs.erase(m->initial_exprs.begin() + g);
    m->initial_origin.erase(m->initial_origin.begin() + g);
  }
  constexpr size_t kNotesShown = 10;
  for (size_t k = 0; k < m->redundant_exprs.size() && k < kNotesShown; ++k) {
    std::string from = m->redundant_from[k];
    for (size_t pos = 0; (pos = from.find('\n', pos)) != std::string::npos; pos += 5) from.replace(pos, 1, "\n    ");
    report->notes.push_back("initial conditions: the " + m->redundant_origin[k] + " is redundant: it follows from\n    " +
                            from + "\n  It is left out of the initial system; initialisation checks that it holds.");
  }
  if (m->redundant_exprs.size() > kNotesShown) {
    report->notes.push_back("initial conditions: " + std::to_string(m->redundant_exprs.size() - kNotesShown) +
                            " more redundant ones are left out and checked the same way (`check -v` lists the "
                            "initial equations kept)");
  }
  const std::vector<uint32_t>& defaulted = plan.defaulted;
  for (uint32_t y : defaulted) {
    VarId v = m->unknowns[y];
    m->initial_exprs.push_back(p.Sub(p.Var(v), sys.guess[v.value()]));
    m->initial_origin.push_back("start value of " + flat.VariableName(v) + " (not fixed; taken as initial condition)");
    m->defaulted_starts.push_back(flat.VariableName(v));
  }
  if (!m->defaulted_starts.empty()) {
    std::ostringstream w;
    const size_t dof = m->state_y.size(), missing = m->defaulted_starts.size();
    w << "initial conditions: the model has " << dof << (dof == 1 ? " degree" : " degrees")
      << " of freedom and its fixed start values and initial equations determine " << dof - missing
      << "; the start " << (missing == 1 ? "value" : "values") << " of ";
    for (size_t k = 0; k < missing && k < 10; ++k) w << (k ? ", " : "") << m->defaulted_starts[k];
    if (missing > 10) w << " and " << missing - 10 << " more";
    w << (missing == 1 ? " is" : " are") << " used as well (add fixed: true to say so)";
    report->warnings.push_back(w.str());
  }

  // Event conditions, from everything that is evaluated.
  ConditionTable conds(&p, names, slots.disc_of_var);
  auto collect_all = [&](auto&& fn) {
    for (ExprId& e : m->residual_exprs) fn(e);
    for (ExprId& e : m->output_exprs) fn(e);
    for (ExprId& e : m->initial_exprs) fn(e);
    for (ExprId& e : m->redundant_exprs) fn(e);
    for (auto& d : sys.discrete) fn(d.value);
    for (auto& w : sys.whens) {
      fn(w.condition);
      for (auto& a : w.assigns) fn(a.second);
      for (auto& r : w.reinits) fn(r.second);
    }
    for (auto& im : sys.impacts) {
      for (ExprId* e : {&im.gap, &im.velocity, &im.release}) fn(*e);
    }
  };
  collect_all([&](ExprId& e) { conds.Collect(e); });
  conds.Freeze();
  std::vector<ExprId> z, dz;
  for (size_t r = 0; r < conds.size(); ++r) {
    const Node rel = p.node(conds.relation(r));
    ExprId zr = conds.Replace(p.Sub(ExprId(rel.a), ExprId(rel.b)));
    bool time_only = !(p.mask(zr) & (kHasVar | kHasDer | kHasPre | kHasCond | kHasInitial));
    z.push_back(zr);
    // A crossing function that reads der() has no rate here (it would need second derivatives).
    ExprId rate = (p.mask(zr) & kHasDer) ? ExprId() : TimeDerivative(&p, zr);
    if (rate.valid()) {
      // Discrete variables are constant between events: their der() is 0, not an unknown's y'.
      std::unordered_map<uint32_t, ExprId> constant;
      for (ExprId leaf : CollectLeaves(p, rate, kHasDer)) {
        const Node der = p.node(leaf);
        if (der.op == Op::kDer && slots.y_of_var[der.a] < 0) constant[leaf.value()] = p.Zero();
      }
      if (!constant.empty()) rate = ReplaceNodes(&p, rate, constant, kHasDer);
    }
    dz.push_back(rate.valid() ? rate : p.Zero());
    m->conditions.push_back({rel.op, time_only, conds.Text(r), rate.valid()});
  }
  collect_all([&](ExprId& e) { e = conds.Replace(e); });
  const uint32_t nc = static_cast<uint32_t>(conds.size());

  ProgramCompiler compiler(p, static_cast<uint32_t>(flat.parameters.size()), slots.y_of_var,
                           slots.disc_of_var, nc);

  // The DAE's residual and Jacobian dF/dy + cj dF/dy', and the initialisation system's
  // partials (columns: y, then the states' y').
  m->residual = compiler.Compile(m->residual_exprs);
  std::vector<Entry> entries, init_entries;
  PartialDerivatives partials(&p);
  // cj * d: most y' partials are the same number (the -1 of v - der(x)), so the last is kept
  // (the same node; only the lookup in the pool is spared).
  ExprId last_d, last_cj_d;
  auto times_cj = [&](ExprId d) {
    if (d != last_d) {
      last_d = d;
      last_cj_d = p.Mul(p.Cj(), d);
    }
    return last_cj_d;
  };
  for (uint32_t i = 0; i < n; ++i) {
    partials.Reset(m->residual_exprs[i], kHasVar | kHasDer);
    for (ExprId leaf : partials.Leaves()) {
      const Node nd_leaf = p.node(leaf);  // a copy: new nodes may move the pool
      int32_t y = slots.y_of_var[nd_leaf.a];
      if (y < 0) continue;
      ExprId d = partials.Of(leaf);
      if (p.IsConst(d, 0)) continue;
      bool der = nd_leaf.op == Op::kDer;
      entries.push_back({static_cast<int32_t>(i), y, der ? times_cj(d) : d, der});
      if (!der) {
        init_entries.push_back({static_cast<int32_t>(i), y, d});
      } else if (slots.state_of_y[y] >= 0) {
        init_entries.push_back({static_cast<int32_t>(i), static_cast<int32_t>(n) + slots.state_of_y[y], d});
      }
    }
  }
  {
    SortColumnMajor(&entries, static_cast<int32_t>(n));
    // A y and a y' partial of one (row, column), now next to each other, make one entry.
    size_t merged = 0;
    for (const Entry& e : entries) {
      if (merged > 0 && entries[merged - 1].row == e.row && entries[merged - 1].col == e.col) {
        entries[merged - 1].value = p.Add(entries[merged - 1].value, e.value);
      } else {
        entries[merged++] = e;
      }
    }
    entries.resize(merged);
    std::vector<ExprId> values;
    SortToPattern(&entries, static_cast<int32_t>(n), static_cast<int32_t>(n), &m->jacobian_pattern, &values);
    std::vector<Entry>().swap(entries);  // given back before the programs that follow
    m->jacobian = compiler.Compile(values);
  }
  {
    std::vector<ExprId> roots = m->residual_exprs;
    roots.insert(roots.end(), m->initial_exprs.begin(), m->initial_exprs.end());
    m->init_residual = compiler.Compile(roots);
    m->redundant_residual = compiler.Compile(m->redundant_exprs);
    for (size_t gi = 0; gi < m->initial_exprs.size(); ++gi) {
      int32_t row = static_cast<int32_t>(n + gi);
      partials.Reset(m->initial_exprs[gi], kHasVar | kHasDer);
      for (ExprId leaf : partials.Leaves()) {
        const Node nd_leaf = p.node(leaf);  // a copy: new nodes may move the pool
        int32_t y = slots.y_of_var[nd_leaf.a];
        if (y < 0) continue;
        bool der = nd_leaf.op == Op::kDer;
        if (der && slots.state_of_y[y] < 0) continue;
        ExprId d = partials.Of(leaf);
        if (p.IsConst(d, 0)) continue;
        int32_t col = der ? static_cast<int32_t>(n) + slots.state_of_y[y] : y;
        init_entries.push_back({row, col, d});
      }
    }
    std::vector<ExprId> values;
    int32_t size = static_cast<int32_t>(n + m->state_y.size());
    SortToPattern(&init_entries, size, size, &m->init_pattern, &values);
    std::vector<Entry>().swap(init_entries);
    m->init_jacobian = compiler.Compile(values);
  }
  m->outputs = compiler.Compile(m->output_exprs);
  {
    std::vector<ExprId> starts;
    for (VarId v : m->unknowns) starts.push_back(sys.guess[v.value()]);
    m->start_values = compiler.Compile(starts);
    m->start_guesses = compiler.Compile(PropagatedStartGuesses(&p, sys, *m, slots));
  }
  {
    std::vector<ExprId> divisors;
    for (const auto& g : m->guards) divisors.push_back(g.divisor);
    m->guard_values = compiler.Compile(divisors);
  }

  // Discrete values: starts, and the equations stored into their registers in order.
  m->discrete_starts = compiler.Compile(discrete_start);
  {
    std::vector<ExprId> values;
    std::vector<uint32_t> registers;
    // Register numbers are known now: disc_base + index (the layout's fixed part).
    for (const auto& d : sys.discrete) {
      values.push_back(d.value);
      m->discrete_equations.emplace_back(d.var, d.value);
      registers.push_back(compiler.layout().disc_base + static_cast<uint32_t>(slots.disc_of_var[d.var.value()]));
    }
    m->discrete_update = compiler.Compile(values, &registers);
  }
  m->zero_crossings = compiler.Compile(z);
  m->zero_crossing_rates = compiler.Compile(dz);

  // When-clauses: conditions, statement values, targets.
  {
    std::vector<ExprId> cond_values, statement_values;
    for (const auto& w : sys.whens) {
      CompiledModel::When cw;
      cw.text = flat.WhenText(flat.whens[w.origin]);
      cond_values.push_back(w.condition);
      for (const auto& [target, value] : w.assigns) {
        int32_t d = slots.disc_of_var[target.value()];
        if (d < 0) throw ModelError(flat.whens[w.origin].loc, "when '" + cw.text + "' assigns " + flat.VariableName(target) + ", which is not a discrete variable");
        cw.assigns.emplace_back(static_cast<uint32_t>(d), static_cast<uint32_t>(statement_values.size()));
        statement_values.push_back(value);
      }
      for (const auto& [target, value] : w.reinits) {
        // The target may have been replaced by an alias: x = c*u + o gives u := (value - o)/c.
        ExprId rep = sys.eliminated->Apply(p.Var(target));
        AffineForm form;
        if (!DecomposeAffine(&p, rep, 1, &form) || form.terms.size() != 1 || p.op(form.terms[0].first) != Op::kVar) {
          throw ModelError(flat.whens[w.origin].loc, "reinit(" + flat.VariableName(target) + ", …) in '" + cw.text + "': the variable is not a state");
        }
        uint32_t u = p.node(form.terms[0].first).a;
        int32_t y = slots.y_of_var[u];
        if (y < 0 || !m->is_state[y]) {
          throw ModelError(flat.whens[w.origin].loc, "reinit(" + flat.VariableName(target) + ", …) in '" + cw.text + "': the variable is not a state (der() of it appears nowhere)");
        }
        cw.reinits.emplace_back(static_cast<uint32_t>(y), static_cast<uint32_t>(statement_values.size()));
        statement_values.push_back(p.Div(p.Sub(value, form.offset), p.Const(form.terms[0].second)));
      }
      m->whens.push_back(std::move(cw));
    }
    sys.eliminated->ReleaseMemo();  // grown again by the reinits' targets
    m->when_conditions = compiler.Compile(cond_values);
    m->when_values = compiler.Compile(statement_values);
  }

  // Impacts: the contact-mode row that carries Newton's law at an impact, and the values the
  // simulator watches (gap, velocity, restitution, v_small, release).
  {
    std::vector<ExprId> values;
    for (const auto& im : sys.impacts) {
      const FlatImpact& fi = flat.impacts[im.origin];
      CompiledModel::Impact ci;
      ci.name = flat.InstancePath(fi.instance);
      auto row = std::find(residual_source.begin(), residual_source.end(), fi.mode_equation);
      if (row == residual_source.end()) {
        throw ModelError(fi.loc, "the impact of " + ci.name + " lost its contact equation during simplification (an internal limitation; please report the model)");
      }
      ci.mode_row = static_cast<uint32_t>(row - residual_source.begin());
      ci.contact = static_cast<uint32_t>(slots.disc_of_var[im.contact.value()]);
      for (ExprId e : {im.gap, im.velocity}) {
        for (ExprId leaf : CollectLeaves(p, e, kHasVar | kHasDer)) {
          const Node leaf_node = p.node(leaf);  // kVar and kDer: a is the variable
          const int32_t y = slots.y_of_var[leaf_node.a];
          if (leaf_node.op == Op::kDer || (y >= 0 && !m->is_state[y])) m->impacts_read_algebraic = true;
        }
      }
      for (ExprId e : {im.gap, im.velocity, im.restitution, im.v_small, im.release}) values.push_back(e);
      m->impacts.push_back(std::move(ci));
    }
    m->impact_values = compiler.Compile(values);
  }

  compiler.Finish({&m->residual, &m->jacobian, &m->outputs, &m->start_values, &m->start_guesses, &m->init_residual, &m->redundant_residual,
                   &m->init_jacobian, &m->guard_values, &m->discrete_starts, &m->discrete_update,
                   &m->zero_crossings, &m->zero_crossing_rates, &m->when_conditions,
                   &m->when_values, &m->impact_values,
                   &compiler.parameter_program()});
  m->parameters = std::move(compiler.parameter_program());
  m->layout = compiler.layout();
  m->constants = compiler.constants();
  std::ostringstream note;
  note << m->residual.size() << " residual, " << m->jacobian.size() << " Jacobian ("
       << m->jacobian_pattern.nnz() << " nonzeros), " << m->parameters.size()
       << " parameter instructions; " << m->initial_exprs.size() << " initial equations";
  if (!defaulted.empty()) note << " (" << defaulted.size() << " start values taken)";
  if (!m->redundant_exprs.empty()) note << " (" << m->redundant_exprs.size() << " redundant left out)";
  if (nc || nd) note << "; " << nc << " event conditions, " << nd << " discrete variables";
  report->compile_note = note.str();
  return m;
}

}  // namespace momenta
